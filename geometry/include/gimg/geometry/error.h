#pragma once
// Errors of the geometry layer. InputError means the user's data is unusable (bad file, wrong
// topology for a method): the CLI prints its one-line message and exits with code 2.

#include <stdexcept>
#include <string>

namespace gimg::geo {

class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace gimg::geo
