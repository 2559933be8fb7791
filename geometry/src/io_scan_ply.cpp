// PLY validation (see io_scan.h). The header is parsed and normalised in io_ply_header.cpp; here
// every element up to the face element is walked (OpenMesh's reader stops after the faces), each
// count checked against the bytes that remain, each coordinate and index checked. OpenMesh gets
// the normalised header followed by just the vertex and face data.

#include "io_ply_header.h"
#include "io_scan.h"
#include "io_text.h"

#include "gimg/geometry/error.h"

#include <cfloat>
#include <cmath>
#include <cstring>

namespace gimg::geo::io {

namespace {

// Reads binary PLY scalars of either byte order.
class BinaryCursor {
public:
    BinaryCursor(std::string_view data, bool big_endian) : data_(data), big_endian_(big_endian) {}

    std::size_t position() const { return pos_; }
    std::size_t remaining() const { return data_.size() - pos_; }
    void skip(std::size_t bytes) { pos_ += bytes; }

    // The value as a double (exact for every PLY type); callers check remaining() first.
    double read(PlyScalar type) {
        unsigned char b[8] = {};
        const std::size_t n = scalar_size(type);
        std::memcpy(b, data_.data() + pos_, n);
        pos_ += n;
        if (big_endian_) {
            for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        }
        switch (type) {
            case PlyScalar::i8:
                return static_cast<std::int8_t>(b[0]);
            case PlyScalar::u8:
                return b[0];
            case PlyScalar::i16: {
                std::int16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case PlyScalar::u16: {
                std::uint16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case PlyScalar::i32: {
                std::int32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyScalar::u32: {
                std::uint32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyScalar::f32: {
                float v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyScalar::f64: {
                double v;
                std::memcpy(&v, b, 8);
                return v;
            }
        }
        return 0;
    }

private:
    std::string_view data_;
    bool big_endian_;
    std::size_t pos_ = 0;
};

struct ElementRange {
    std::size_t begin = 0;
    std::size_t end = 0;
};

std::string element_item(const PlyElement& e, std::size_t i) { return e.name + " " + std::to_string(i); }

// The coordinate the reader makes of a binary value (it casts double to float).
float checked_coordinate(double value, const PlyElement& e, std::size_t i) {
    if (!std::isfinite(value)) {
        throw InputError(element_item(e, i) + " has a NaN or infinite coordinate");
    }
    if (std::fabs(value) > FLT_MAX) {
        throw InputError(element_item(e, i) + ": coordinate " + std::to_string(value) + " is out of range for float");
    }
    return static_cast<float>(value);
}

// The least number of bytes the binary data of `e` can take (lists at their shortest).
std::uint64_t min_binary_bytes(const PlyElement& e) {
    std::uint64_t per_item = 0;
    for (const PlyProperty& p : e.properties) {
        per_item += scalar_size(p.is_list ? p.count_type : p.type);
        if (p.role == PlyRole::indices) per_item += 3 * scalar_size(p.type);
    }
    return per_item * e.count;
}

void scan_binary(std::string_view data, const PlyHeader& h, ScanResult& scan, ElementRange ranges[2]) {
    BinaryCursor in(data, h.encoding == PlyEncoding::binary_big_endian);
    const std::uint32_t vertex_count = h.elements[h.vertex_element].count;
    const std::size_t last = std::max(h.vertex_element, h.face_element);

    std::uint64_t need = 0;
    for (std::size_t k = 0; k <= last; ++k) need += min_binary_bytes(h.elements[k]);
    if (need > data.size()) {
        throw InputError("the PLY header declares " + std::to_string(vertex_count) + " vertices and " +
                         std::to_string(h.elements[h.face_element].count) + " faces, which need at least " +
                         std::to_string(need) + " bytes, but only " + std::to_string(data.size()) +
                         " bytes of data follow (truncated file, or a header that lies)");
    }

    for (std::size_t k = 0; k <= last; ++k) {
        const PlyElement& e = h.elements[k];
        const std::size_t begin = in.position();
        const bool is_vertex = k == h.vertex_element;
        for (std::size_t i = 0; i < e.count; ++i) {
            float xyz[3] = {};
            for (const PlyProperty& p : e.properties) {
                if (!p.is_list) {
                    if (in.remaining() < scalar_size(p.type)) {
                        throw InputError("the data ends inside " + element_item(e, i) + " of " +
                                         std::to_string(e.count) + " (truncated)");
                    }
                    if (!is_vertex || p.role == PlyRole::skip) {
                        in.skip(scalar_size(p.type));
                        continue;
                    }
                    // Texture coordinates go through the same float conversion as positions.
                    const float value = checked_coordinate(in.read(p.type), e, i);
                    if (p.role >= PlyRole::x && p.role <= PlyRole::z) {
                        xyz[static_cast<int>(p.role) - static_cast<int>(PlyRole::x)] = value;
                    }
                    continue;
                }
                if (in.remaining() < scalar_size(p.count_type)) {
                    throw InputError("the data ends inside " + element_item(e, i) + " (truncated)");
                }
                const double count = in.read(p.count_type);
                if (count < 0 ||
                    static_cast<double>(in.remaining()) < count * static_cast<double>(scalar_size(p.type))) {
                    throw InputError(element_item(e, i) + ": list " + quoted(p.name) + " declares " +
                                     std::to_string(static_cast<long long>(count)) +
                                     " entries, more than the data holds (truncated or corrupted)");
                }
                const auto entries = static_cast<std::uint32_t>(count);
                if (p.role != PlyRole::indices) {
                    in.skip(entries * scalar_size(p.type));
                    continue;
                }
                if (entries < 3) {
                    throw InputError("face " + std::to_string(i) + " has " + std::to_string(entries) +
                                     " vertices (a face needs at least 3)");
                }
                scan.face_fingerprint.add(entries);
                for (std::uint32_t c = 0; c < entries; ++c) {
                    const double index = in.read(p.type);
                    if (index < 0 || index >= vertex_count) {
                        throw InputError("face " + std::to_string(i) + " names vertex " +
                                         std::to_string(static_cast<long long>(index)) + ", but the file has " +
                                         std::to_string(vertex_count) + " vertices");
                    }
                    scan.face_fingerprint.add(static_cast<std::uint32_t>(index));
                }
            }
            if (is_vertex) scan.vertex_fingerprint.add_position(xyz[0], xyz[1], xyz[2]);
        }
        if (is_vertex) ranges[0] = {begin, in.position()};
        if (k == h.face_element) ranges[1] = {begin, in.position()};
    }
}

// Ascii data: one item per line (blank lines between are allowed), exactly the declared values.
void scan_ascii(std::string_view data, const PlyHeader& h, ScanResult& scan, ElementRange ranges[2]) {
    require_text(data, "PLY");
    const std::uint32_t vertex_count = h.elements[h.vertex_element].count;
    const std::size_t last = std::max(h.vertex_element, h.face_element);

    // Each item takes at least two bytes per value ("0 " or "0\n").
    std::uint64_t need = 0;
    for (std::size_t k = 0; k <= last; ++k) {
        const PlyElement& e = h.elements[k];
        need += std::uint64_t{e.count} * 2 * e.properties.size();
    }
    if (need > data.size() + 1) {
        throw InputError("the PLY header declares " + std::to_string(vertex_count) + " vertices and " +
                         std::to_string(h.elements[h.face_element].count) + " faces, which need at least " +
                         std::to_string(need) + " bytes, but only " + std::to_string(data.size()) +
                         " bytes of data follow (truncated file, or a header that lies)");
    }

    LineReader lines(data, 0, h.data_line);
    std::string_view line;
    for (std::size_t k = 0; k <= last; ++k) {
        const PlyElement& e = h.elements[k];
        const bool is_vertex = k == h.vertex_element;
        std::size_t begin = lines.position();
        for (std::size_t i = 0; i < e.count; ++i) {
            if (!lines.next_nonblank(line)) {
                throw InputError("the file ends after " + std::to_string(i) + " of " + std::to_string(e.count) +
                                 " items of element " + quoted(e.name) + " (truncated)");
            }
            const std::string where = "line " + std::to_string(lines.line_number()) + ": " + element_item(e, i);
            Tokens t(line);
            auto next_token = [&](const PlyProperty& p) -> std::string_view {
                std::string_view tok;
                if (!t.next(tok)) throw InputError(where + " lacks a value for " + quoted(p.name));
                return tok;
            };
            float xyz[3] = {};
            for (const PlyProperty& p : e.properties) {
                if (!p.is_list) {
                    const std::string_view tok = next_token(p);
                    if (!is_vertex || p.role == PlyRole::skip) continue;  // the reader skips any token
                    float value = 0;
                    if (const Number status = parse_float(tok, value); status != Number::ok) {
                        throw InputError(where + ": " + number_problem(status, tok));
                    }
                    if (p.role >= PlyRole::x && p.role <= PlyRole::z) {
                        xyz[static_cast<int>(p.role) - static_cast<int>(PlyRole::x)] = value;
                    }
                    continue;
                }
                std::uint32_t entries = 0;
                const std::string_view count = next_token(p);
                if (!parse_uint32(count, entries)) {
                    throw InputError(where + ": list count " + quoted(count) + " is not a whole number");
                }
                if (p.role == PlyRole::indices) {
                    if (entries < 3) {
                        throw InputError(where + " has " + std::to_string(entries) +
                                         " vertices (a face needs at least 3)");
                    }
                    scan.face_fingerprint.add(entries);
                }
                for (std::uint32_t c = 0; c < entries; ++c) {
                    const std::string_view tok = next_token(p);
                    if (p.role != PlyRole::indices) continue;
                    std::uint32_t index = 0;
                    if (!parse_uint32(tok, index)) {
                        throw InputError(where + ": vertex index " + quoted(tok) + " is not a whole number");
                    }
                    if (index >= vertex_count) {
                        throw InputError(where + " names vertex " + std::to_string(index) + ", but the file has " +
                                         std::to_string(vertex_count) + " vertices");
                    }
                    scan.face_fingerprint.add(index);
                }
            }
            if (!t.at_end()) throw InputError(where + " has more values than the header declares");
            if (is_vertex) scan.vertex_fingerprint.add_position(xyz[0], xyz[1], xyz[2]);
            if (i == 0) begin = lines.line_start();
        }
        if (is_vertex) ranges[0] = {begin, lines.position()};
        if (k == h.face_element) ranges[1] = {begin, lines.position()};
    }
}

}  // namespace

ScanResult scan_ply(std::string_view bytes) {
    const PlyHeader header = parse_ply_header(bytes);
    const std::string_view data = bytes.substr(header.data_start);
    ScanResult scan;
    scan.format = "ply";
    scan.encoding = header.encoding_name;
    scan.vertices = header.elements[header.vertex_element].count;
    scan.faces = header.elements[header.face_element].count;
    scan.reader_faces = scan.faces;
    scan.has_texcoords = header.has_texcoords;
    scan.notes = header.notes;

    ElementRange ranges[2];  // vertex, face
    if (header.encoding == PlyEncoding::ascii) {
        scan_ascii(data, header, scan, ranges);
    } else {
        scan_binary(data, header, scan, ranges);
    }
    scan.reader_bytes = normalised_ply_header(header);
    for (const ElementRange& r : ranges) {
        scan.reader_bytes.append(data.substr(r.begin, r.end - r.begin));
        // An ascii element may end the file without a newline; the next must start on a new line.
        if (header.encoding == PlyEncoding::ascii && scan.reader_bytes.back() != '\n') scan.reader_bytes += '\n';
    }
    return scan;
}

}  // namespace gimg::geo::io
