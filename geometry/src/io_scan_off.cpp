// OFF validation (see io_scan.h). OpenMesh's OFF reader reads "[C][N]OFF", then the counts with
// operator>>, then per vertex three (six with normals) floats and the rest of the line (colours),
// then per face a count, that many indices and, for COFF only, the rest of the line. It does not
// know comments, counts on the OFF line, or face colours in a plain OFF file, and it never checks
// the stream, so all of that is checked or normalised here.

#include "io_scan.h"
#include "io_text.h"

#include "gimg/geometry/error.h"

#include <cstring>

namespace gimg::geo::io {

namespace {

struct OffHeader {
    bool colors = false;   // C: vertex colours on the vertex lines, face colours on face lines
    bool normals = false;  // N: three more floats per vertex
    std::string keyword;
};

// The header keyword in the order OpenMesh parses it: [ST][C][N][4][n]OFF [BINARY].
OffHeader parse_keyword(std::string_view keyword) {
    OffHeader h;
    h.keyword = std::string(keyword);
    std::string_view k = keyword;
    auto unsupported = [&](const std::string& why) {
        throw InputError("OFF variant " + quoted(keyword) + " is not supported (" + why + ")");
    };
    if (k.size() < 3 || k.substr(k.size() - 3) != "OFF") {
        throw InputError("not an OFF file: the first line starts with " + quoted(keyword) + " instead of OFF");
    }
    k.remove_suffix(3);
    if (k.substr(0, 2) == "ST") unsupported("texture coordinates");
    if (!k.empty() && k.front() == 'C') {
        h.colors = true;
        k.remove_prefix(1);
    }
    if (!k.empty() && k.front() == 'N') {
        h.normals = true;
        k.remove_prefix(1);
    }
    if (!k.empty() && (k.front() == '4' || k.front() == 'n')) unsupported("only 3D vertices are read");
    if (!k.empty()) unsupported("unknown prefix");
    return h;
}

// Overwrites '#' comments with spaces so that the reader, which knows no comments, sees blanks.
void blank_comments(std::string& text) {
    bool in_comment = false;
    for (char& c : text) {
        if (c == '\n')
            in_comment = false;
        else if (c == '#')
            in_comment = true;
        if (in_comment) c = ' ';
    }
}

}  // namespace

ScanResult scan_off(std::string_view bytes) {
    // Say "binary OFF" rather than "binary data in a text file" for an OFF BINARY header.
    if (const std::string_view first = bytes.substr(0, bytes.find('\n'));
        first.find("OFF") != std::string_view::npos && first.find("BINARY") != std::string_view::npos) {
        throw InputError("binary OFF files are not supported (write ascii OFF, or PLY)");
    }
    require_text(bytes, "OFF");
    std::string text(bytes);
    blank_comments(text);

    LineReader lines(text);
    std::string_view line;
    if (!lines.next_nonblank(line)) throw InputError("the file holds no OFF header, only blanks or comments");
    Tokens header_tokens(line);
    std::string_view token;
    header_tokens.next(token);
    const OffHeader header = parse_keyword(token);
    std::string_view counts_line = line.substr(header_tokens.position());
    if (Tokens(counts_line).at_end()) {
        if (!lines.next_nonblank(counts_line)) throw InputError("the OFF header has no vertex and face counts");
    }
    std::uint32_t counts[3] = {0, 0, 0};
    {
        Tokens t(counts_line);
        int n = 0;
        while (t.next(token)) {
            if (n == 3 || !parse_uint32(token, counts[n])) {
                throw InputError("line " + std::to_string(lines.line_number()) +
                                 ": OFF counts must be three whole numbers (vertices faces edges), found " +
                                 quoted(token));
            }
            ++n;
        }
        if (n < 2) {
            throw InputError("line " + std::to_string(lines.line_number()) +
                             ": OFF counts need at least the number of vertices and of faces");
        }
    }
    const std::uint32_t vertex_count = counts[0];
    const std::uint32_t face_count = counts[1];
    if (vertex_count == 0) throw InputError("the OFF header declares no vertices");
    if (face_count == 0) throw InputError("the OFF header declares no faces (gimg needs triangles)");

    // Every vertex line holds at least "0 0 0\n", every face line at least a count and a
    // newline: a header whose counts the rest of the file cannot hold is a lie or a truncation;
    // say so before scanning.
    const std::uint64_t min_bytes = 6ull * vertex_count + 2ull * face_count - 1;
    const std::uint64_t body_bytes = text.size() - lines.position();
    if (min_bytes > body_bytes) {
        throw InputError("the OFF header declares " + std::to_string(vertex_count) + " vertices and " +
                         std::to_string(face_count) + " faces, which need at least " + std::to_string(min_bytes) +
                         " bytes, but only " + std::to_string(body_bytes) +
                         " follow (truncated file, or a header that lies)");
    }

    ScanResult scan;
    scan.format = "off";
    scan.encoding = "ascii";
    scan.vertices = vertex_count;
    scan.faces = face_count;
    scan.reader_faces = face_count;

    const std::size_t body_start = lines.position();
    const int coords_per_vertex = header.normals ? 6 : 3;
    for (std::uint32_t v = 0; v < vertex_count; ++v) {
        if (!lines.next_nonblank(line)) {
            throw InputError("the file ends after " + std::to_string(v) + " of " + std::to_string(vertex_count) +
                             " vertices (truncated)");
        }
        Tokens t(line);
        float xyz[6] = {};
        for (int i = 0; i < coords_per_vertex; ++i) {
            if (!t.next(token)) {
                throw InputError("line " + std::to_string(lines.line_number()) + ": vertex " + std::to_string(v) +
                                 " has " + std::to_string(i) + " of " + std::to_string(coords_per_vertex) + " numbers");
            }
            if (Number status = parse_float(token, xyz[i]); status != Number::ok) {
                throw InputError("line " + std::to_string(lines.line_number()) + ": vertex " + std::to_string(v) +
                                 ": " + number_problem(status, token));
            }
        }
        scan.vertex_fingerprint.add_position(xyz[0], xyz[1], xyz[2]);
    }

    // Plain OFF: the reader stops after the indices and would read a face colour as the next
    // face's count, so whatever follows the indices is blanked out (COFF readers skip it).
    for (std::uint32_t f = 0; f < face_count; ++f) {
        if (!lines.next_nonblank(line)) {
            throw InputError("the file ends after " + std::to_string(f) + " of " + std::to_string(face_count) +
                             " faces (truncated)");
        }
        const std::string where = "line " + std::to_string(lines.line_number()) + ": face " + std::to_string(f);
        Tokens t(line);
        std::uint32_t corners = 0;
        t.next(token);
        if (!parse_uint32(token, corners)) {
            throw InputError(where + ": the vertex count " + quoted(token) + " is not a whole number");
        }
        if (corners < 3) {
            throw InputError(where + " has " + std::to_string(corners) + " vertices (a face needs at least 3)");
        }
        scan.face_fingerprint.add(corners);
        for (std::uint32_t i = 0; i < corners; ++i) {
            std::uint32_t index = 0;
            if (!t.next(token)) {
                throw InputError(where + " declares " + std::to_string(corners) + " vertices but lists " +
                                 std::to_string(i));
            }
            if (!parse_uint32(token, index)) {
                throw InputError(where + ": vertex index " + quoted(token) + " is not a whole number");
            }
            if (index >= vertex_count) {
                throw InputError(where + " names vertex " + std::to_string(index) + ", but the file has " +
                                 std::to_string(vertex_count) + " vertices");
            }
            scan.face_fingerprint.add(index);
        }
        if (!header.colors && !t.at_end()) {
            const std::size_t from = lines.line_start() + t.position();
            std::memset(text.data() + from, ' ', line.size() - t.position());
        }
    }

    scan.reader_bytes = header.keyword + "\n" + std::to_string(vertex_count) + " " + std::to_string(face_count) + " " +
                        std::to_string(counts[2]) + "\n";
    scan.reader_bytes.append(text, body_start, std::string::npos);
    return scan;
}

}  // namespace gimg::geo::io
