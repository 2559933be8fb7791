#pragma once
// Each gimg command lives in its own cmd_<name>.cpp and registers itself on the CLI11 app here.

#include <CLI/CLI.hpp>

namespace gimg::cli {

struct GlobalOptions {
    bool verbose = false;
    bool quiet = false;
};

// gimg info MESH [--json FILE] [--weld] (cmd_info.cpp)
void add_info_command(CLI::App& app, const GlobalOptions& global);

}  // namespace gimg::cli
