#pragma once
// gimg's error policy for the caller's data, in every layer above the engine:
//  - Data a method cannot use (a mesh file, a mesh with the wrong topology for the method, an
//    image, a frame, a sparse matrix, a size or an option value) throws geo::InputError, its
//    message one line that names the input and the defect ("genus 3: spherical parameterization
//    needs genus 0", "linear system: column 12 out of range (size 10)").
//  - The machine's limits and failures (no device, a missing feature, out of memory, device loss,
//    a failed Vulkan call) and misuse of the render graph throw gimg::Error with its ErrorKind
//    (gimg/engine/error.h).
//  - The disk failing under a write (full, read-only, an I/O error) throws geo::EnvironmentError.
// The command line prints each message as `gimg: error: ...` and exits with 2 for InputError,
// 1 for gimg::Error and EnvironmentError.

#include <stdexcept>
#include <string>

namespace gimg::geo {

class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

class EnvironmentError : public std::runtime_error {
public:
    explicit EnvironmentError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace gimg::geo
