#pragma once
// nlohmann's exception texts begin with an id ("[json.exception.out_of_range.403] key 'size' not
// found"); a user's message is what follows it.
#include <nlohmann/json.hpp>

#include <string>

namespace gimg::passes::detail {

inline std::string json_problem(const nlohmann::json::exception& e) {
    const std::string what = e.what();
    const auto end = what.find("] ");
    return what.rfind("[json.exception.", 0) == 0 && end != std::string::npos ? what.substr(end + 2) : what;
}

}  // namespace gimg::passes::detail
