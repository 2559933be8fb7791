#pragma once
// This gimg executable run again as a child process: for benchmarks whose figures differ from one
// process to the next (where the machine places a process's memory and threads), so that each
// run is measured in a process of its own.

#include <string>
#include <vector>

namespace gimg::cli {

// Runs `gimg ARGS...` (this executable) and waits for it; its output goes where this process's
// goes. Returns its exit code (128 + the signal's number when a signal ended it).
int run_gimg(const std::vector<std::string>& args);

}  // namespace gimg::cli
