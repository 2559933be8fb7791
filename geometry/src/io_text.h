#pragma once
// Text scanning for the mesh-file validators (io_scan_*.cpp). The validators must accept only what
// OpenMesh's readers read correctly, so numbers are recognised exactly as std::istream's
// operator>> recognises them in the "C" locale, only stricter: a token must be a number as a
// whole ("1.5x" is rejected here, while operator>> would read 1.5 and then fail on "x").

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace gimg::geo::io {

// Whitespace as operator>> sees it in the "C" locale.
constexpr bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

// Throws InputError when `text` holds bytes no text mesh file holds (NUL and other control
// characters): a binary or corrupted file given a text format's extension.
void require_text(std::string_view text, std::string_view format_name);

// A token for an error message: printable, short, quoted.
std::string quoted(std::string_view token);

// Lines split at '\n' (as std::getline splits them); the '\n' is not part of the line.
class LineReader {
public:
    explicit LineReader(std::string_view text, std::size_t start = 0, std::size_t first_line = 1)
        : text_(text), pos_(start), next_line_(first_line) {}
    // The next line, or false at the end of the text.
    bool next(std::string_view& line);
    // The next line holding a token; false at the end.
    bool next_nonblank(std::string_view& line);
    std::size_t line_number() const { return line_; }  // of the line last returned, 1-based
    std::size_t line_start() const { return start_; }  // byte offset of that line
    std::size_t position() const { return pos_; }      // byte offset after that line's '\n'

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t start_ = 0;
    std::size_t line_ = 0;
    std::size_t next_line_ = 1;
};

// Whitespace-separated tokens of one line.
class Tokens {
public:
    explicit Tokens(std::string_view line) : line_(line) {}
    bool next(std::string_view& token);
    // Offset (within the line) just past the last token returned.
    std::size_t position() const { return pos_; }
    bool at_end();  // no token left

private:
    std::string_view line_;
    std::size_t pos_ = 0;
};

// The line with surrounding whitespace removed.
std::string_view trim(std::string_view line);

enum class Number { ok, not_a_number, nan_or_inf, out_of_range };

// As `stream >> float` and `stream >> double` read it (OpenMesh 9's readers all read float):
// optional sign, digits with an optional point, optional exponent. Overflow is out_of_range (the
// stream would fail); underflow gives what strtof/strtod give, as the stream does.
Number parse_float(std::string_view token, float& value);
Number parse_double(std::string_view token, double& value);
// Digits only; false when not a number or above 4294967295.
bool parse_uint32(std::string_view token, std::uint32_t& value);
// Optional sign and digits within the range of int (as `stream >> int`).
bool parse_int(std::string_view token, std::int64_t& value);

// A message for a coordinate that parse_float/parse_double refused.
std::string number_problem(Number status, std::string_view token);

}  // namespace gimg::geo::io
