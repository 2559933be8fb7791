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

// Paths a signal handler acts on, as C strings: temporary files to unlink, folders to remove if
// empty. A slot is claimed with one atomic flag and read by the handler only once its path is
// whole; 64 of each at once is far more than any command makes.
constexpr std::size_t kSlots = 64, kPathBytes = 4096;

struct SignalPaths {
    std::array<std::atomic<bool>, kSlots> claimed{}, ready{};
    std::array<std::array<char, kPathBytes>, kSlots> path{};

    int add(const fs::path& p) {
        const std::string s = p.string();
        if (s.size() >= kPathBytes) return -1;
        for (std::size_t i = 0; i < kSlots; ++i) {
            bool expected = false;
            if (claimed[i].compare_exchange_strong(expected, true)) {
                std::memcpy(path[i].data(), s.c_str(), s.size() + 1);
                ready[i].store(true);
                return int(i);
            }
        }
        return -1;  // not acted on at a signal, still removed on errors
    }
    void remove(int slot) {
        if (slot < 0) return;
        ready[std::size_t(slot)].store(false);
        claimed[std::size_t(slot)].store(false);
    }
};
SignalPaths g_temps, g_folders;

void on_signal(int sig) {
    for (std::size_t i = 0; i < kSlots; ++i)
        if (g_temps.ready[i].load()) ::unlink(g_temps.path[i].data());
    // rmdir fails on a folder that is not empty: pass after pass empties nested ones whatever
    // their slots' order.
    for (bool removed = true; removed;) {
        removed = false;
        for (std::size_t i = 0; i < kSlots; ++i)
            if (g_folders.ready[i].load() && ::rmdir(g_folders.path[i].data()) == 0) {
                g_folders.ready[i].store(false);
                removed = true;
            }
    }
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

thread_local OutputSet* t_current = nullptr;

// A temporary file's registration, removed with the file unless released.
struct Temp {
    fs::path path;
    int slot = -1;
    bool keep = false;
    explicit Temp(fs::path p) : path(std::move(p)), slot(g_temps.add(path)) {}
    ~Temp() {
        if (keep) return;
        std::error_code ec;
        fs::remove(path, ec);
        g_temps.remove(slot);
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
    g_temps.remove(temp.slot);
}

std::error_code create_output_folder(const fs::path& dir) {
    std::error_code ec;
    std::vector<fs::path> missing;  // deepest first; a path that cannot be checked counts as there
    for (fs::path p = dir.lexically_normal(); !p.empty(); p = p.parent_path()) {
        if (fs::exists(p, ec) || ec) break;
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
        g_temps.remove(f.slot);
    }
    for (auto it = folders_.rbegin(); it != folders_.rend(); ++it) {
        std::error_code ec;
        if (fs::is_directory(it->path, ec) && fs::is_empty(it->path, ec)) fs::remove(it->path, ec);
        g_folders.remove(it->slot);
    }
}

void OutputSet::add(fs::path temp, fs::path target, int slot) {
    files_.push_back({std::move(temp), std::move(target), slot});
}

void OutputSet::add_folder(fs::path dir) {
    const int slot = g_folders.add(dir);
    folders_.push_back({std::move(dir), slot});
}

void OutputSet::commit() {
    if (t_current == this) t_current = outer_;
    if (outer_) {
        for (Pending& f : files_) outer_->files_.push_back(std::move(f));
        files_.clear();
        for (Folder& d : folders_) outer_->folders_.push_back(std::move(d));
        folders_.clear();
        done_ = true;
        return;
    }
    for (const Pending& f : files_) rename_into_place(f.temp, f.target);  // a failure leaves the rest to ~OutputSet
    for (const Pending& f : files_) g_temps.remove(f.slot);
    for (const Folder& d : folders_) g_folders.remove(d.slot);
    done_ = true;
}

void remove_outputs_on_signals() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
}

}  // namespace gimg::geo
