// OBJ validation (see io_scan.h). OpenMesh's OBJ reader reads the file twice: first every
// "v x y z" as floats (silently skipping one it cannot parse, which shifts every later index) and
// "vt u v" (failing the whole read on one it cannot parse),
// then the faces. Per face corner "v[/vt[/vn]]" it parses each part with operator>> without
// checking the stream, removes repeated vertices of a face and drops faces left with fewer than
// three. It also opens any "mtllib" file, whatever that path names. So here every vertex must
// parse, every corner must be well formed and in range, faces the reader alters are recorded as
// the file states them (load_mesh puts them back), and material lines are blanked out.

#include "io_scan.h"
#include "io_text.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gimg::geo::io {

namespace {

// The keyword of a line as the reader finds it: it trims " \t\r\n" and skips empty lines,
// comments and lines starting with other whitespace.
bool keyword_of(std::string_view line, Tokens& tokens, std::string_view& keyword) {
    std::size_t b = 0, e = line.size();
    auto trimmed_char = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (b < e && trimmed_char(line[b])) ++b;
    while (e > b && trimmed_char(line[e - 1])) --e;
    if (b == e || line[b] == '#' || is_space(line[b])) return false;
    tokens = Tokens(line);
    return tokens.next(keyword);
}

struct Corner {
    std::int64_t vertex = 0;
    std::int64_t texcoord = 0;  // 0: none
};

// "v", "v/vt", "v//vn", "v/vt/vn" (and "v/", "v/vt/"): the vertex index is required, the others
// may be empty; each part a whole number.
bool parse_corner(std::string_view block, Corner& corner) {
    std::string_view parts[3];
    int n = 0;
    while (true) {
        const std::size_t slash = block.find('/');
        parts[n++] = block.substr(0, slash);
        if (slash == std::string_view::npos) break;
        if (n == 3) return false;
        block.remove_prefix(slash + 1);
    }
    std::int64_t value = 0;
    if (!parse_int(parts[0], value)) return false;
    corner.vertex = value;
    corner.texcoord = 0;
    if (n > 1 && !parts[1].empty()) {
        if (!parse_int(parts[1], value)) return false;
        corner.texcoord = value;
    }
    if (n > 2 && !parts[2].empty() && !parse_int(parts[2], value)) return false;
    return true;
}

// An OBJ index (1-based, or negative: relative to the elements read so far) as 0-based, or -1.
std::int64_t resolve(std::int64_t index, std::int64_t seen_so_far, std::int64_t total) {
    const std::int64_t i = index > 0 ? index - 1 : seen_so_far + index;
    return (index != 0 && i >= 0 && i < total) ? i : -1;
}

}  // namespace

ScanResult scan_obj(std::string_view bytes) {
    require_text(bytes, "OBJ");
    std::string text(bytes);
    ScanResult scan;
    scan.format = "obj";
    scan.encoding = "ascii";

    // Pass 1, like the reader's: vertices and texture coordinates.
    std::int64_t vertex_total = 0, texcoord_total = 0;
    LineReader lines(text);
    std::string_view line, keyword, token;
    Tokens tokens("");
    while (lines.next(line)) {
        if (!keyword_of(line, tokens, keyword)) continue;
        const std::string where = "line " + std::to_string(lines.line_number());
        if (keyword == "v") {
            float xyz[3] = {};
            for (float& c : xyz) {
                if (!tokens.next(token)) throw InputError(where + ": a vertex needs three coordinates");
                if (const Number status = parse_float(token, c); status != Number::ok) {
                    throw InputError(where + ": vertex " + std::to_string(vertex_total + 1) + ": " +
                                     number_problem(status, token));
                }
            }
            scan.vertex_fingerprint.add_position(xyz[0], xyz[1], xyz[2]);
            ++vertex_total;
        } else if (keyword == "vt") {
            for (int i = 0; i < 2; ++i) {
                float value = 0;
                if (!tokens.next(token)) throw InputError(where + ": a texture coordinate needs two numbers");
                if (const Number status = parse_float(token, value); status != Number::ok) {
                    throw InputError(where + ": texture coordinate: " + number_problem(status, token));
                }
            }
            ++texcoord_total;
        }
    }
    scan.vertices = static_cast<std::size_t>(vertex_total);
    if (vertex_total == 0) throw InputError("the OBJ file has no vertices ('v' lines)");

    // Pass 2: faces, with the running counts negative indices are relative to.
    std::int64_t vertices_seen = 0, texcoords_seen = 0;
    bool corners_with_texcoords = false;
    LineReader faces(text);
    std::vector<std::uint32_t> corners, reduced;
    while (faces.next(line)) {
        if (!keyword_of(line, tokens, keyword)) continue;
        if (keyword == "mtllib" || keyword == "usemtl") {
            // gimg reads geometry only; the reader would open whatever file mtllib names.
            std::memset(text.data() + faces.line_start(), ' ', line.size());
            continue;
        }
        if (keyword == "v") ++vertices_seen;
        if (keyword == "vt") ++texcoords_seen;
        if (keyword != "f") continue;
        const std::string where =
            "line " + std::to_string(faces.line_number()) + ": face " + std::to_string(scan.faces + 1);
        corners.clear();
        while (tokens.next(token)) {
            Corner c;
            if (!parse_corner(token, c)) {
                throw InputError(where + ": cannot read corner " + quoted(token) +
                                 " (expected v, v/vt, v//vn or v/vt/vn)");
            }
            const std::int64_t v = resolve(c.vertex, vertices_seen, vertex_total);
            if (v < 0) {
                throw InputError(where + " names vertex " + std::to_string(c.vertex) + ", but the file has " +
                                 std::to_string(vertex_total) + " vertices (OBJ counts from 1)");
            }
            if (c.texcoord != 0) {
                if (resolve(c.texcoord, texcoords_seen, texcoord_total) < 0) {
                    throw InputError(where + " names texture coordinate " + std::to_string(c.texcoord) +
                                     ", but the file has " + std::to_string(texcoord_total));
                }
                corners_with_texcoords = true;
            }
            corners.push_back(static_cast<std::uint32_t>(v));
        }
        if (corners.size() < 3) {
            throw InputError(where + " has " + std::to_string(corners.size()) + " vertices (a face needs at least 3)");
        }
        reduced.clear();
        for (std::uint32_t v : corners) {
            if (std::find(reduced.begin(), reduced.end(), v) == reduced.end()) reduced.push_back(v);
        }
        const bool delivered = reduced.size() >= 3;
        if (reduced.size() != corners.size()) {
            scan.kept_faces.push_back({scan.faces, delivered, corners});
        }
        if (delivered) {
            scan.face_fingerprint.add(reduced.size());
            for (std::uint32_t v : reduced) scan.face_fingerprint.add(v);
            ++scan.reader_faces;
        }
        ++scan.faces;
    }
    if (scan.faces == 0) throw InputError("the OBJ file has no faces ('f' lines)");
    scan.has_texcoords = corners_with_texcoords;
    if (!scan.kept_faces.empty()) {
        scan.notes.push_back(std::to_string(scan.kept_faces.size()) +
                             " faces repeat a vertex; kept as the file states them (degenerate)");
    }
    scan.reader_bytes = std::move(text);
    return scan;
}

}  // namespace gimg::geo::io
