#include "io_text.h"

#include "gimg/geometry/error.h"

#include <array>
#include <cctype>
#include <clocale>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <cstdlib>
#include <limits>
#include <locale.h>

namespace gimg::geo::io {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// The syntax operator>> accumulates for a floating-point value: [+-] digits [. digits] [e [+-] digits],
// with at least one mantissa digit; the exponent needs a digit or strtod stops before it.
bool is_decimal_number(std::string_view s) {
    std::size_t i = 0;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t mantissa_digits = 0;
    while (i < s.size() && is_digit(s[i])) {
        ++i;
        ++mantissa_digits;
    }
    if (i < s.size() && s[i] == '.') {
        ++i;
        while (i < s.size() && is_digit(s[i])) {
            ++i;
            ++mantissa_digits;
        }
    }
    if (mantissa_digits == 0) return false;
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        std::size_t exponent_digits = 0;
        while (i < s.size() && is_digit(s[i])) {
            ++i;
            ++exponent_digits;
        }
        if (exponent_digits == 0) return false;
    }
    return i == s.size();
}

bool is_nan_or_inf(std::string_view s) {
    if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
    std::string lower;
    for (char c : s.substr(0, 8)) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return lower.rfind("nan", 0) == 0 || lower.rfind("inf", 0) == 0;
}

// strtof/strtod need a terminated string in the "C" locale whatever the program's locale is.
locale_t c_locale() {
    static locale_t loc = newlocale(LC_ALL_MASK, "C", static_cast<locale_t>(nullptr));
    return loc;
}

template <typename T>
Number parse_real(std::string_view token, T& value) {
    if (!is_decimal_number(token)) {
        return is_nan_or_inf(token) ? Number::nan_or_inf : Number::not_a_number;
    }
    std::array<char, 64> small{};
    std::string large;
    const char* cstr = nullptr;
    if (token.size() < small.size()) {
        token.copy(small.data(), token.size());
        cstr = small.data();
    } else {
        large.assign(token);
        cstr = large.c_str();
    }
    if constexpr (std::is_same_v<T, float>) {
        value = strtof_l(cstr, nullptr, c_locale());
    } else {
        value = strtod_l(cstr, nullptr, c_locale());
    }
    if (std::isinf(value)) return Number::out_of_range;
    return Number::ok;
}

}  // namespace

void require_text(std::string_view text, std::string_view format_name) {
    std::size_t line = 1;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c == '\n') ++line;
        if (c < 0x20 && !is_space(static_cast<char>(c))) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "0x%02x", c);
            throw InputError("line " + std::to_string(line) + ": binary data (byte " + hex + " at offset " +
                             std::to_string(i) + "): not a text " + std::string(format_name) +
                             " file, or a corrupted one");
        }
    }
}

std::string quoted(std::string_view token) {
    constexpr std::size_t max_chars = 24;
    std::string out = "'";
    for (std::size_t i = 0; i < token.size() && i < max_chars; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
    }
    if (token.size() > max_chars) out += "...";
    return out + "'";
}

bool LineReader::next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    start_ = pos_;
    line_ = next_line_++;
    const std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) {
        line = text_.substr(pos_);
        pos_ = text_.size();
    } else {
        line = text_.substr(pos_, end - pos_);
        pos_ = end + 1;
    }
    return true;
}

bool LineReader::next_nonblank(std::string_view& line) {
    while (next(line)) {
        if (!trim(line).empty()) return true;
    }
    return false;
}

bool Tokens::next(std::string_view& token) {
    while (pos_ < line_.size() && is_space(line_[pos_])) ++pos_;
    if (pos_ >= line_.size()) return false;
    const std::size_t begin = pos_;
    while (pos_ < line_.size() && !is_space(line_[pos_])) ++pos_;
    token = line_.substr(begin, pos_ - begin);
    return true;
}

bool Tokens::at_end() {
    while (pos_ < line_.size() && is_space(line_[pos_])) ++pos_;
    return pos_ >= line_.size();
}

std::string_view trim(std::string_view line) {
    while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
    while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
    return line;
}

Number parse_float(std::string_view token, float& value) { return parse_real(token, value); }
Number parse_double(std::string_view token, double& value) { return parse_real(token, value); }

bool parse_uint32(std::string_view token, std::uint32_t& value) {
    if (token.empty() || token.size() > 10) return false;
    std::uint64_t v = 0;
    for (char c : token) {
        if (!is_digit(c)) return false;
        v = v * 10 + static_cast<std::uint64_t>(c - '0');
    }
    if (v > std::numeric_limits<std::uint32_t>::max()) return false;
    value = static_cast<std::uint32_t>(v);
    return true;
}

bool parse_int(std::string_view token, std::int64_t& value) {
    bool negative = false;
    if (!token.empty() && (token[0] == '+' || token[0] == '-')) {
        negative = token[0] == '-';
        token.remove_prefix(1);
    }
    if (token.empty() || token.size() > 10) return false;
    std::int64_t v = 0;
    for (char c : token) {
        if (!is_digit(c)) return false;
        v = v * 10 + (c - '0');
    }
    if (negative) v = -v;
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) return false;
    value = v;
    return true;
}

std::string number_problem(Number status, std::string_view token) {
    switch (status) {
        case Number::nan_or_inf:
            return "NaN or infinite coordinate " + quoted(token);
        case Number::out_of_range:
            return "coordinate " + quoted(token) + " is out of range for float";
        case Number::not_a_number:
            return quoted(token) + " is not a number";
        case Number::ok:
            break;
    }
    return "coordinate " + quoted(token);
}

}  // namespace gimg::geo::io
