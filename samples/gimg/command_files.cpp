#include "command_files.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <system_error>

namespace gimg::cli {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// Whether two paths name one file: the same inode when both exist, else the same normal path.
bool same_file(const fs::path& a, const fs::path& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) out += (i ? (i + 1 == items.size() ? " or " : ", ") : "") + items[i];
    return out;
}

// A whole number in [lo, hi], written in decimal digits only; the option's name in the message.
unsigned long long ranged_count(const std::string& name, const std::string& text, unsigned long long lo,
                                unsigned long long hi) {
    const bool digits = !text.empty() && text.size() <= 20 && text.find_first_not_of("0123456789") == std::string::npos;
    const unsigned long long v = digits ? std::stoull(text) : 0;
    if (!digits || v < lo || v > hi)
        throw geo::InputError(name + " takes a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                              ", got '" + text + "'");
    return v;
}

template <class T>
CLI::Option* add_ranged(CLI::App* cmd, const std::string& name, T& value, T lo, T hi, const std::string& help) {
    return cmd
        ->add_option_function<std::string>(
            name, [&value, name, lo, hi](const std::string& text) { value = T(ranged_count(name, text, lo, hi)); },
            help)
        ->type_name("N");
}

// A bound as a user would write it: 1000000, 0.999, 1e-15 (std::to_string gives 1000000.000000).
std::string bound_text(double x) {
    std::ostringstream s;
    s.precision(15);
    s << x;
    return s.str();
}

}  // namespace

std::vector<OutputFile> folder_outputs(const std::string& option, const fs::path& dir,
                                       const std::vector<std::string>& names) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw geo::InputError(option + " " + dir.string() + " is a file; it takes a folder (created if missing)");
    std::vector<OutputFile> out;
    for (const std::string& name : names) out.push_back({option, dir / name, {}});
    return out;
}

void check_picture_shows_something(const geo::RgbaImage& picture, const std::string& what) {
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4)
        if (picture.pixels[i] != 0) return;
    throw geo::InputError(what + ": the picture shows nothing (the faces are too small or degenerate to draw)");
}

void make_output_folder(const std::string& option, const fs::path& dir) {
    std::error_code ec = geo::create_output_folder(dir);
    if (ec || !fs::is_directory(dir, ec))
        throw geo::InputError(option + " " + dir.string() + ": cannot create the folder (" + ec.message() + ")");
}

void check_command_files(const std::vector<fs::path>& inputs, const std::vector<OutputFile>& outputs) {
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const OutputFile& o = outputs[i];
        if (o.path.empty() || (o.option == "--json" && o.path == "-")) continue;
        std::error_code ec;
        const fs::file_status status = fs::symlink_status(o.path, ec);
        if (fs::exists(status) && !fs::is_regular_file(status)) {
            try {
                geo::check_output_target(o.path);
            } catch (const geo::InputError& e) {
                throw geo::InputError(o.option + ": " + e.what() +
                                      (o.option == "--json" ? "; --json - writes to standard output" : ""));
            }
        }
        if (!o.extensions.empty() &&
            std::find(o.extensions.begin(), o.extensions.end(), lower_extension(o.path)) == o.extensions.end())
            throw geo::InputError(o.option + " " + o.path.string() + ": the file name must end in " +
                                  join(o.extensions));
        for (const fs::path& in : inputs)
            if (!in.empty() && same_file(in, o.path))
                throw geo::InputError(o.option + " " + o.path.string() +
                                      " is an input of this command; write elsewhere");
        for (std::size_t k = 0; k < i; ++k)
            if (!outputs[k].path.empty() && same_file(outputs[k].path, o.path))
                throw geo::InputError(o.option + " " + o.path.string() + " is also written as " + outputs[k].option +
                                      "; give each output its own file");
    }
}

CLI::Option* add_number_option(CLI::App* cmd, const std::string& name, double& value, double lo, double hi,
                               const std::string& help) {
    return cmd
        ->add_option_function<std::string>(
            name,
            [&value, name, lo, hi](const std::string& text) {
                const bool decimal = !text.empty() && text.find_first_not_of("0123456789.eE+-") == std::string::npos;
                char* end = nullptr;
                errno = 0;
                const double v = decimal ? std::strtod(text.c_str(), &end) : 0.0;
                if (!decimal || errno != 0 || end != text.c_str() + text.size() || !(v >= lo && v <= hi))
                    throw geo::InputError(name + " takes a number from " + bound_text(lo) + " to " + bound_text(hi) +
                                          ", got '" + text + "'");
                value = v;
            },
            help)
        ->type_name("X");
}

CLI::Option* add_count_option(CLI::App* cmd, const std::string& name, std::uint64_t& value, std::uint64_t lo,
                              std::uint64_t hi, const std::string& help) {
    return add_ranged(cmd, name, value, lo, hi, help);
}

CLI::Option* add_count_option(CLI::App* cmd, const std::string& name, std::uint32_t& value, std::uint32_t lo,
                              std::uint32_t hi, const std::string& help) {
    return add_ranged(cmd, name, value, lo, hi, help);
}

CLI::Option* add_count_list_option(CLI::App* cmd, const std::string& name, std::vector<std::uint32_t>& values,
                                   std::uint32_t lo, std::uint32_t hi, const std::string& help) {
    return cmd
        ->add_option_function<std::vector<std::string>>(
            name,
            [&values, name, lo, hi](const std::vector<std::string>& texts) {
                values.clear();
                for (const std::string& text : texts) values.push_back(std::uint32_t(ranged_count(name, text, lo, hi)));
            },
            help)
        ->type_name("N");
}

passes::View parse_view(const std::string& text) {
    passes::View v;
    if (text.empty()) return v;
    std::istringstream in(text);
    char comma = 0;
    if (!(in >> v.azimuth_deg >> comma >> v.elevation_deg) || comma != ',' || !in.eof() ||
        std::abs(v.elevation_deg) > 90.0 || !std::isfinite(v.azimuth_deg))
        throw geo::InputError("--view takes AZ,EL in degrees (elevation in [-90, 90]), got '" + text + "'");
    return v;
}

}  // namespace gimg::cli
