#pragma once
// The command line's half of the output policy (the library's half is gimg/geometry/atomic_file.h):
// before any work, every output is checked (a new or regular file, its format's extension, not an
// input, not another output), so a command that will refuse does so before its first file.

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/image.h"
#include "gimg/passes/render.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace gimg::cli {

struct OutputFile {
    std::string option;                   // how the user named it: "--out", "--json"
    std::filesystem::path path;           // empty: not asked for
    std::vector<std::string> extensions;  // lower case with the dot; empty: any
};

// The files a command writes into `--out DIR` (DIR may not exist yet; it must not be a file).
std::vector<OutputFile> folder_outputs(const std::string& option, const std::filesystem::path& dir,
                                       const std::vector<std::string>& names);

// Creates an output folder (and its parents); geo::InputError naming the option if it cannot.
void make_output_folder(const std::string& option, const std::filesystem::path& dir);

// Throws geo::InputError naming the option when an output is not a new or regular file, lacks its
// extension, is one of `inputs`, or is the same file as another output. `--json -` (standard
// output) passes.
void check_command_files(const std::vector<std::filesystem::path>& inputs, const std::vector<OutputFile>& outputs);

// A --json output: a .json file, or "-" for standard output.
inline OutputFile json_output(const std::string& path) { return {"--json", path, {".json"}}; }

// Runs a command's body with its files checked first and written as one set (geo::OutputSet):
// they appear together when the body returns, or not at all.
template <class Body>
void run_writing(const std::vector<std::filesystem::path>& inputs, const std::vector<OutputFile>& outputs,
                 Body&& body) {
    check_command_files(inputs, outputs);
    geo::OutputSet files;
    body();
    files.commit();
}

// Throws geo::InputError when a rendered picture shows nothing (alpha 0 everywhere): a blank
// picture is a failure, not a result.
void check_picture_shows_something(const geo::RgbaImage& picture, const std::string& what);

// Range-checked numeric options: decimal only (no hex, no sign for counts), the option's name in
// the message. An integer option in [lo, hi]:
CLI::Option* add_count_option(CLI::App* cmd, const std::string& name, std::uint64_t& value, std::uint64_t lo,
                              std::uint64_t hi, const std::string& help);
CLI::Option* add_count_option(CLI::App* cmd, const std::string& name, std::uint32_t& value, std::uint32_t lo,
                              std::uint32_t hi, const std::string& help);
// The same for an option taking several integers, each in [lo, hi]; given, they replace the defaults.
CLI::Option* add_count_list_option(CLI::App* cmd, const std::string& name, std::vector<std::uint32_t>& values,
                                   std::uint32_t lo, std::uint32_t hi, const std::string& help);
// A decimal number in [lo, hi] (no hex, inf or nan).
CLI::Option* add_number_option(CLI::App* cmd, const std::string& name, double& value, double lo, double hi,
                               const std::string& help);

// --view AZ,EL: camera azimuth and elevation in degrees; empty gives the renderer's default.
passes::View parse_view(const std::string& text);

}  // namespace gimg::cli
