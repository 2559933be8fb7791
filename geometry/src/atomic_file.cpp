#include "gimg/geometry/atomic_file.h"

#include "gimg/geometry/error.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include <unistd.h>

namespace gimg::geo {

namespace fs = std::filesystem;

namespace {

// Temporary files in flight, as C strings a signal handler can unlink. A slot is taken with an
// atomic flag; 64 files at once is far more than any command writes.
constexpr std::size_t kSlots = 64, kPathBytes = 4096;
std::array<std::atomic<bool>, kSlots> g_slot_used{};
std::array<std::array<char, kPathBytes>, kSlots> g_slot_path{};

int register_temp(const fs::path& temp) {
    const std::string s = temp.string();
    if (s.size() >= kPathBytes) return -1;
    for (std::size_t i = 0; i < kSlots; ++i) {
        bool expected = false;
        if (g_slot_used[i].compare_exchange_strong(expected, true)) {
            std::memcpy(g_slot_path[i].data(), s.c_str(), s.size() + 1);
            return int(i);
        }
    }
    return -1;  // not removable on a signal, still removed on errors
}

void unregister_temp(int slot) {
    if (slot >= 0) g_slot_used[std::size_t(slot)].store(false);
}

void on_signal(int sig) {
    for (std::size_t i = 0; i < kSlots; ++i)
        if (g_slot_used[i].load()) ::unlink(g_slot_path[i].data());
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

thread_local OutputSet* t_current = nullptr;

// A temporary file's registration, removed with the file unless released.
struct Temp {
    fs::path path;
    int slot = -1;
    bool keep = false;
    explicit Temp(fs::path p) : path(std::move(p)), slot(register_temp(path)) {}
    ~Temp() {
        if (keep) return;
        std::error_code ec;
        fs::remove(path, ec);
        unregister_temp(slot);
    }
};

std::string temp_prefix(const fs::path& target) {
    std::string prefix(1, '.');
    prefix.append(target.filename().string()).append(".gimg-");
    return prefix;
}

// Temporary files of this target left by processes that no longer run.
void remove_stale_temps(const fs::path& target) {
    const std::string prefix = temp_prefix(target);
    std::error_code ec;
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) != 0 || name.size() < prefix.size() + 5 || name.substr(name.size() - 4) != ".tmp")
            continue;
        std::string pid = name.substr(prefix.size(), name.size() - 4 - prefix.size());
        pid = pid.substr(0, pid.find('-'));
        if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
        errno = 0;
        if (::kill(pid_t(std::stol(pid)), 0) == -1 && errno == ESRCH) fs::remove(it->path(), ec);
    }
}

void rename_into_place(const fs::path& temp, const fs::path& target) {
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) throw EnvironmentError("cannot write " + target.string() + ": " + ec.message());
}

}  // namespace

void check_output_target(const fs::path& path) {
    if (path.empty()) throw InputError("an output path is empty");
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(path, ec);
    if (fs::exists(status) && !fs::is_regular_file(status))
        throw InputError(path.string() + " exists and is not a regular file (" +
                         (fs::is_symlink(status)     ? std::string("a symbolic link")
                          : fs::is_directory(status) ? std::string("a folder")
                                                     : std::string("a device or pipe")) +
                         "); gimg writes only new or regular files");
    const fs::path dir = path.parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError("cannot write " + path.string() + ": folder " + dir.string() + " does not exist");
}

void write_file_atomically(const fs::path& path, std::string_view contents) {
    check_output_target(path);
    remove_stale_temps(path);
    static std::atomic<unsigned> counter{0};
    Temp temp(path.parent_path() /
              (temp_prefix(path) + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".tmp"));
    {
        std::ofstream out(temp.path, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError("cannot write " + path.string() + ": the folder is not writable");
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.flush();
        if (!out) throw EnvironmentError("cannot write " + path.string() + ": the write failed (disk full?)");
    }
    if (t_current) {
        t_current->add(temp.path, path, temp.slot);  // the set owns it now
        temp.keep = true;
        return;
    }
    rename_into_place(temp.path, path);
    temp.keep = true;
    unregister_temp(temp.slot);
}

std::error_code create_output_folder(const fs::path& dir) {
    std::error_code ec;
    std::vector<fs::path> missing;  // deepest first
    for (fs::path p = dir.lexically_normal(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    fs::create_directories(dir, ec);
    if (ec) return ec;
    if (t_current)
        for (auto it = missing.rbegin(); it != missing.rend(); ++it) t_current->add_folder(*it);
    return {};
}

OutputSet::OutputSet() : outer_(t_current) { t_current = this; }

OutputSet::~OutputSet() {
    if (t_current == this) t_current = outer_;
    if (done_) return;
    for (const Pending& f : files_) {
        std::error_code ec;
        fs::remove(f.temp, ec);
        unregister_temp(f.slot);
    }
    for (auto it = folders_.rbegin(); it != folders_.rend(); ++it) {
        std::error_code ec;
        if (fs::is_directory(*it, ec) && fs::is_empty(*it, ec)) fs::remove(*it, ec);
    }
}

void OutputSet::add(fs::path temp, fs::path target, int slot) {
    files_.push_back({std::move(temp), std::move(target), slot});
}

void OutputSet::add_folder(fs::path dir) { folders_.push_back(std::move(dir)); }

void OutputSet::commit() {
    if (t_current == this) t_current = outer_;
    if (outer_) {
        for (Pending& f : files_) outer_->files_.push_back(std::move(f));
        files_.clear();
        for (fs::path& d : folders_) outer_->folders_.push_back(std::move(d));
        folders_.clear();
        done_ = true;
        return;
    }
    for (const Pending& f : files_) rename_into_place(f.temp, f.target);  // a failure leaves the rest to ~OutputSet
    for (const Pending& f : files_) unregister_temp(f.slot);
    done_ = true;
}

void remove_outputs_on_signals() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
}

}  // namespace gimg::geo
