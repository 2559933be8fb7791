// STL validation (see io_scan.h). OpenMesh's STL reader takes a file for binary when its size is
// exactly 84 + 50 * (the triangle count in bytes 80..83), and for ascii otherwise. Ascii: any line
// containing "outer" (or "OUTER") starts a facet and the next three lines are read as
// "<word> x y z" without checking the stream (a short or garbled line repeats the last vertex).
// Both merge corners at the same position into one vertex (through a std::map with a tolerant
// comparison) and drop facets two of whose corners merged. The merging is replayed here exactly,
// so the scan knows every vertex and face the reader hands over, and records the dropped facets
// for load_mesh to put back.

#include "io_scan.h"
#include "io_text.h"

#include "gimg/geometry/error.h"

#include <glm/vec3.hpp>

#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <map>

namespace gimg::geo::io {

namespace {

constexpr std::size_t kBinaryHeader = 84;
constexpr std::size_t kBinaryFacet = 50;

// The reader's corner order (OpenMesh's CmpVec with eps = FLT_MIN), in the same float arithmetic:
// corners no coordinate of which differs by more than FLT_MIN are the same vertex.
struct CornerLess {
    bool operator()(const glm::vec3& a, const glm::vec3& b) const {
        if (std::fabs(a[0] - b[0]) <= FLT_MIN) {
            if (std::fabs(a[1] - b[1]) <= FLT_MIN) return a[2] < b[2] - FLT_MIN;
            return a[1] < b[1] - FLT_MIN;
        }
        return a[0] < b[0] - FLT_MIN;
    }
};

// Replays the reader: each corner is looked up in a map of the corners seen so far and becomes a
// new vertex when not found; a facet with two corners on one vertex is dropped by the reader.
class FacetCollector {
public:
    explicit FacetCollector(ScanResult& scan) : scan_(scan) {}

    void add(const std::array<glm::vec3, 3>& corners) {
        std::uint32_t v[3];
        for (int k = 0; k < 3; ++k) {
            const glm::vec3& c = corners[static_cast<std::size_t>(k)];
            auto it = vertices_.find(c);
            if (it == vertices_.end()) {
                it = vertices_.emplace(c, static_cast<std::uint32_t>(scan_.vertices++)).first;
                scan_.vertex_fingerprint.add_position(c.x, c.y, c.z);
            }
            v[k] = it->second;
        }
        if (v[0] == v[1] || v[0] == v[2] || v[1] == v[2]) {
            scan_.kept_faces.push_back({scan_.faces, false, {v[0], v[1], v[2]}});
        } else {
            scan_.face_fingerprint.add(3);
            for (std::uint32_t i : v) scan_.face_fingerprint.add(i);
            ++scan_.reader_faces;
        }
        ++scan_.faces;
    }

private:
    ScanResult& scan_;
    std::map<glm::vec3, std::uint32_t, CornerLess> vertices_;
};

bool looks_binary(std::string_view bytes) {
    for (char c : bytes.substr(0, 512)) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 && !is_space(c)) return true;
    }
    return bytes.substr(0, 5) != "solid";
}

void scan_binary(std::string_view bytes, ScanResult& scan) {
    scan.encoding = "binary";
    FacetCollector facets(scan);
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);  // little endian, like the reader on this machine
    for (std::uint32_t f = 0; f < count; ++f) {
        const char* record = bytes.data() + kBinaryHeader + std::size_t{f} * kBinaryFacet;
        float v[12];
        std::memcpy(v, record, sizeof v);  // normal, then three corners
        std::array<glm::vec3, 3> corners;
        for (int k = 0; k < 3; ++k) {
            for (int a = 0; a < 3; ++a) {
                const float x = v[3 + 3 * k + a];
                if (!std::isfinite(x)) {
                    throw InputError("facet " + std::to_string(f) + " has a NaN or infinite coordinate");
                }
                corners[static_cast<std::size_t>(k)][a] = x;
            }
        }
        facets.add(corners);
    }
}

void scan_ascii(std::string_view bytes, ScanResult& scan) {
    scan.encoding = "ascii";
    require_text(bytes, "STL");
    FacetCollector facets(scan);
    LineReader lines(bytes);
    std::string_view line, token;
    while (lines.next(line)) {
        if (line.find("outer") == std::string_view::npos && line.find("OUTER") == std::string_view::npos) continue;
        const std::size_t facet_line = lines.line_number();
        std::array<glm::vec3, 3> corners;
        for (int k = 0; k < 3; ++k) {
            if (!lines.next(line)) {
                throw InputError("the file ends inside the facet starting on line " + std::to_string(facet_line) +
                                 " (truncated)");
            }
            const std::string where = "line " + std::to_string(lines.line_number());
            Tokens t(line);
            if (!t.next(token) || (token != "vertex" && token != "VERTEX")) {
                throw InputError(where + ": expected 'vertex x y z' (line " + std::to_string(facet_line) +
                                 " contains 'outer', which starts a facet for OpenMesh's STL reader)");
            }
            for (int a = 0; a < 3; ++a) {
                float x = 0;
                if (!t.next(token)) throw InputError(where + ": a vertex needs three coordinates");
                if (const Number status = parse_float(token, x); status != Number::ok) {
                    throw InputError(where + ": " + number_problem(status, token));
                }
                corners[static_cast<std::size_t>(k)][a] = x;
            }
        }
        facets.add(corners);
    }
}

}  // namespace

ScanResult scan_stl(std::string_view bytes) {
    ScanResult scan;
    scan.format = "stl";
    if (bytes.size() >= kBinaryHeader) {
        std::uint32_t count = 0;
        std::memcpy(&count, bytes.data() + 80, 4);
        const std::uint64_t binary_size = kBinaryHeader + std::uint64_t{count} * kBinaryFacet;
        if (binary_size == bytes.size()) {
            scan_binary(bytes, scan);
        } else if (looks_binary(bytes)) {
            throw InputError("binary STL: the header declares " + std::to_string(count) + " triangles, which need " +
                             std::to_string(binary_size) + " bytes, but the file has " + std::to_string(bytes.size()) +
                             " (truncated file, or a header that lies)");
        } else {
            scan_ascii(bytes, scan);
        }
    } else {
        if (looks_binary(bytes)) {
            throw InputError("the file is too short for a binary STL (" + std::to_string(bytes.size()) +
                             " bytes) and is not ascii STL");
        }
        scan_ascii(bytes, scan);
    }
    if (scan.faces == 0) throw InputError("the STL file has no facets");
    if (!scan.kept_faces.empty()) {
        scan.notes.push_back(std::to_string(scan.kept_faces.size()) +
                             " facets have two corners at the same position; kept (degenerate)");
    }
    scan.reader_bytes = std::string(bytes);
    return scan;
}

}  // namespace gimg::geo::io
