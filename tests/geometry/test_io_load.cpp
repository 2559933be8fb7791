// load_mesh on valid files: every format and the variants OpenMesh's readers get wrong on their own.
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"

#include "mesh_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using gimg::geo::load_mesh;
using gimg::geo::LoadOptions;
using gimg::geo::LoadReport;
using gimg::geo::Mesh;
using gimg::test::seed_mesh;
using gimg::test::write_file;

namespace {

// The tetrahedron of tests/data/meshes (see its README).
const std::vector<glm::dvec3> kTetraPositions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<glm::uvec3> kTetraFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

void expect_tetra(const Mesh& m) {
    EXPECT_EQ(m.positions, kTetraPositions);
    EXPECT_EQ(m.triangles, kTetraFaces);
}

template <typename T>
void put(std::string& out, T value, bool big_endian = false) {
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

const char* kTetraOffBody = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

}  // namespace

TEST(LoadOff, Tetrahedron) {
    LoadReport report;
    const Mesh m = load_mesh(seed_mesh("tetra.off"), {}, &report);
    expect_tetra(m);
    EXPECT_EQ(report.format, "off");
    EXPECT_EQ(report.encoding, "ascii");
    EXPECT_EQ(report.file_vertices, 4u);
    EXPECT_EQ(report.file_faces, 4u);
    EXPECT_FALSE(report.welded);
    EXPECT_FALSE(m.has_texcoords());
}

TEST(LoadOff, ColoursAndCommentsAreSkipped) { expect_tetra(load_mesh(seed_mesh("tetra_colors.off"))); }

// OpenMesh's OFF reader alone reads no vertex at all from these; the loader normalises them.
TEST(LoadOff, CountsOnTheOffLineAndTwoCounts) {
    expect_tetra(
        load_mesh(write_file("io_load", "counts_on_off_line.off", std::string("OFF 4 4 6\n") + kTetraOffBody)));
    expect_tetra(load_mesh(write_file("io_load", "two_counts.off", std::string("OFF\n4 4\n") + kTetraOffBody)));
}

TEST(LoadOff, CommentsAndBlankLinesAnywhere) {
    const std::string text =
        "# made by hand\nOFF # the keyword\n\n4 4 6 # counts\n0 0 0\n# a comment line\n1 0 0\n\n"
        "0 1 0 # trailing comment\n0 0 1\n3 0 2 1\n3 0 1 3 # face comment\n3 0 3 2\n3 1 2 3";
    expect_tetra(load_mesh(write_file("io_load", "comments.off", text)));
}

// Geomview allows a colour after a face's indices in any OFF file; OpenMesh would read it as
// the next face's vertex count.
TEST(LoadOff, FaceColoursInPlainOff) {
    const std::string text =
        "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 1 0 0\n3 0 1 3 0 1 0\n"
        "3 0 3 2 0 0 1\n3 1 2 3 0.5 0.5 0.5\n";
    expect_tetra(load_mesh(write_file("io_load", "face_colours.off", text)));
}

TEST(LoadOff, NormalsPerVertex) {
    const std::string text =
        "NOFF\n4 4 6\n0 0 0 -1 -1 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n"
        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    expect_tetra(load_mesh(write_file("io_load", "normals.off", text)));
}

TEST(LoadOff, PolygonsAreFanTriangulatedAndCounted) {
    const std::string text = "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 2 0\n4 0 1 2 3\n3 1 4 2\n";
    LoadReport report;
    const Mesh m = load_mesh(write_file("io_load", "quad.off", text), {}, &report);
    EXPECT_EQ(m.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}, {1, 4, 2}}));
    EXPECT_EQ(report.file_faces, 2u);
    EXPECT_EQ(report.polygons_triangulated, 1u);
}

TEST(LoadOff, DuplicateAndNonManifoldFacesAreAllKept) {
    // Three faces on edge 0-1 and the first face twice: a halfedge mesh keeps only some of them.
    const std::string text = "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n3 0 1 2\n";
    const Mesh m = load_mesh(write_file("io_load", "non_manifold.off", text));
    EXPECT_EQ(m.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {0, 1, 2}}));
}

TEST(LoadPly, AsciiAndBinaryTetrahedra) {
    LoadReport report;
    expect_tetra(load_mesh(seed_mesh("tetra_ascii.ply"), {}, &report));
    EXPECT_EQ(report.encoding, "ascii");
    const Mesh m = load_mesh(seed_mesh("tetra_binary.ply"), {}, &report);
    expect_tetra(m);
    EXPECT_EQ(report.encoding, "binary_little_endian");
    ASSERT_TRUE(m.has_texcoords());
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {  // s = x/2 + 1/4, t = y/2 + 1/4 in that file
        EXPECT_EQ(m.texcoords[i], glm::dvec2(m.positions[i].x * 0.5 + 0.25, m.positions[i].y * 0.5 + 0.25));
    }
}

namespace {

// A binary tetrahedron PLY with the given header lines between format and end_header and the
// given per-vertex and per-face extra bytes.
std::string binary_tetra_ply(bool big_endian, const std::string& coordinate_type = "float",
                             const std::string& last_header_line = "") {
    std::string out = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 4\nproperty " + coordinate_type + " x\nproperty " + coordinate_type +
                      " y\nproperty " + coordinate_type +
                      " z\nelement face 4\nproperty list uchar int vertex_indices\n" + last_header_line +
                      "end_header\n";
    for (const glm::dvec3& p : kTetraPositions) {
        for (int k = 0; k < 3; ++k) {
            if (coordinate_type == "double" || coordinate_type == "float64")
                put(out, p[k], big_endian);
            else
                put(out, static_cast<float>(p[k]), big_endian);
        }
    }
    for (const glm::uvec3& t : kTetraFaces) {
        put(out, std::uint8_t{3});
        for (int k = 0; k < 3; ++k) put(out, static_cast<std::int32_t>(t[k]), big_endian);
    }
    return out;
}

}  // namespace

TEST(LoadPly, BigEndianAndDoubleCoordinates) {
    expect_tetra(load_mesh(write_file("io_load", "big_endian.ply", binary_tetra_ply(true))));
    expect_tetra(load_mesh(write_file("io_load", "double.ply", binary_tetra_ply(false, "double"))));
    expect_tetra(load_mesh(write_file("io_load", "double_be.ply", binary_tetra_ply(true, "float64"))));
}

// OpenMesh's reader starts binary data one byte late after such a header (its own files never
// end a header with a comment), and reads garbage.
TEST(LoadPly, CommentJustBeforeEndHeader) {
    expect_tetra(
        load_mesh(write_file("io_load", "comment_last.ply", binary_tetra_ply(false, "float", "comment last\n"))));
    expect_tetra(
        load_mesh(write_file("io_load", "obj_info_last.ply", binary_tetra_ply(false, "float", "obj_info x\n"))));
}

TEST(LoadPly, ExtraPropertiesAndElementsAreSkipped) {
    // Normals, uchar colours, a face flag, an element before and one after the faces, a list in
    // an element OpenMesh does not know.
    std::string out =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
        "property uchar green\nproperty uchar blue\nelement material 1\nproperty list uchar float rgb\n"
        "property double shininess\nelement face 4\nproperty list uint8 uint32 vertex_indices\n"
        "property short flags\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    for (const glm::dvec3& p : kTetraPositions) {
        for (int k = 0; k < 3; ++k) put(out, static_cast<float>(p[k]));
        for (int k = 0; k < 3; ++k) put(out, 0.5f);
        for (int k = 0; k < 3; ++k) put(out, std::uint8_t{200});
    }
    put(out, std::uint8_t{3});
    for (float c : {0.1f, 0.2f, 0.3f}) put(out, c);
    put(out, 12.5);
    for (const glm::uvec3& t : kTetraFaces) {
        put(out, std::uint8_t{3});
        for (int k = 0; k < 3; ++k) put(out, static_cast<std::uint32_t>(t[k]));
        put(out, std::int16_t{-7});
    }
    put(out, std::int32_t{0});
    put(out, std::int32_t{1});
    LoadReport report;
    expect_tetra(load_mesh(write_file("io_load", "extras.ply", out), {}, &report));
    EXPECT_EQ(report.notes.size(), 2u);  // the two elements skipped
}

TEST(LoadPly, AsciiWithFacesBeforeVerticesAndOtherCountTypes) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement face 4\nproperty list int uint vertex_indices\n"
        "property uchar flags\nelement vertex 4\nproperty double x\nproperty double y\n"
        "property double z\nproperty float confidence\nend_header\n"
        "3 0 2 1 9\n3 0 1 3 9\n3 0 3 2 9\n3 1 2 3 9\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1";
    expect_tetra(load_mesh(write_file("io_load", "faces_first.ply", text)));
}

TEST(LoadObj, QuadsTexcoordsAndMaterialsIgnored) {
    LoadReport report;
    const Mesh m = load_mesh(seed_mesh("cube_quads.obj"), {}, &report);
    EXPECT_EQ(m.vertex_count(), 8u);
    EXPECT_EQ(m.face_count(), 12u);
    EXPECT_EQ(report.file_faces, 6u);
    EXPECT_EQ(report.polygons_triangulated, 6u);
    ASSERT_TRUE(m.has_texcoords());
    // Each vertex is a corner of three quads; all but two get different texture coordinates
    // from them (seams): vertex 1 is corner 1 (vt 1) and vertex 8 corner 3 (vt 3) of all three.
    EXPECT_EQ(report.texcoord_conflicts, 6u);
    for (const glm::dvec2& t : m.texcoords) {
        EXPECT_TRUE((t.x == 0.0 || t.x == 1.0) && (t.y == 0.0 || t.y == 1.0));
    }
}

TEST(LoadObj, NegativeIndicesAndForwardReferences) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -1 -2\nf 1 2 4\nv 0 0 1\nf -4 -1 -2\nf 2 3 4\n";
    const Mesh m = load_mesh(write_file("io_load", "negative.obj", text));
    expect_tetra(m);
}

// OpenMesh's OBJ reader removes a face's repeated vertices and drops faces left with fewer than
// three; the loader keeps them as the file has them (info reports them as degenerate).
TEST(LoadObj, FacesRepeatingAVertexAreKept) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 2\nf 1 2 3\nf 1 2 1 4\nf 1 3 4\n";
    LoadReport report;
    const Mesh m = load_mesh(write_file("io_load", "repeats.obj", text), {}, &report);
    EXPECT_EQ(m.triangles, (std::vector<glm::uvec3>{{0, 1, 1}, {0, 1, 2}, {0, 1, 0}, {0, 0, 3}, {0, 2, 3}}));
    EXPECT_EQ(report.file_faces, 4u);
    ASSERT_FALSE(report.notes.empty());
}

// OpenMesh 9 reads OBJ coordinates as float, not as double then float: the two differ just above
// a halfway point between two floats (1 + 2^-24 here).
TEST(LoadObj, CoordinatesAreReadAsFloats) {
    const std::string text = "v 1.0000000596046448 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";
    const Mesh m = load_mesh(write_file("io_load", "halfway.obj", text));
    EXPECT_EQ(m.positions[0].x, 1.0 + std::ldexp(1.0, -23));
}

TEST(LoadStl, AsciiAndBinaryMergeCorners) {
    for (const char* name : {"tetra_ascii.stl", "tetra_binary.stl"}) {
        LoadReport report;
        const Mesh m = load_mesh(seed_mesh(name), {}, &report);
        EXPECT_EQ(m.vertex_count(), 4u) << name;
        ASSERT_EQ(m.face_count(), 4u) << name;
        // Vertices are numbered in order of first appearance, so compare positions per corner.
        for (std::size_t f = 0; f < 4; ++f) {
            for (int k = 0; k < 3; ++k) EXPECT_EQ(m.positions[m.triangles[f][k]], kTetraPositions[kTetraFaces[f][k]]);
        }
        EXPECT_TRUE(report.welded) << name;
        EXPECT_EQ(report.file_vertices, 12u) << name;
        EXPECT_EQ(report.welded_vertices, 8u) << name;
    }
}

// OpenMesh's STL reader drops a facet whose corners coincide; the loader puts it back in place.
TEST(LoadStl, DegenerateFacetsAreKept) {
    std::string out(80, ' ');
    put(out, std::uint32_t{3});
    const float facets[3][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 0, 0, 0, 0, 1}, {1, 0, 0, 0, 1, 0, 0, 0, 1}};
    for (const auto& facet : facets) {
        for (int k = 0; k < 3; ++k) put(out, 0.0f);
        for (float c : facet) put(out, c);
        out.append(2, '\0');
    }
    LoadReport report;
    const Mesh m = load_mesh(write_file("io_load", "degenerate.stl", out), {}, &report);
    ASSERT_EQ(m.face_count(), 3u);
    EXPECT_EQ(m.triangles[1][0], m.triangles[1][1]);  // the middle facet, corners 0 and 1 equal
    EXPECT_EQ(m.positions[m.triangles[1][2]], glm::dvec3(0, 0, 1));
    EXPECT_EQ(m.vertex_count(), 4u);
}

// OpenMesh merges STL corners no coordinate of which differs by more than FLT_MIN; with values
// around FLT_MIN that is not transitive (a fuzzer finding): 1.1e-38 joins 0, 1.7e-38 joins 1.1e-38,
// but 1.7e-38 and 0 are apart. The loader follows the reader's choice.
TEST(LoadStl, CornersMergeWithinFltMin) {
    std::string out(80, ' ');
    put(out, std::uint32_t{2});
    const float a = 1.1130076e-38f, b = 1.7586497e-38f;
    const float facets[2][9] = {{a, 0, 0, b, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 1, 0, 0, 0, 1}};
    for (const auto& facet : facets) {
        for (int k = 0; k < 3; ++k) put(out, 0.0f);
        for (float c : facet) put(out, c);
        out.append(2, '\0');
    }
    const Mesh m = load_mesh(write_file("io_load", "flt_min.stl", out));
    ASSERT_EQ(m.face_count(), 2u);
    EXPECT_EQ(m.vertex_count(), 3u);                  // a, (0,0,1), (0,1,0): b and 0 joined a
    EXPECT_EQ(m.triangles[0][0], m.triangles[0][1]);  // so the first facet is degenerate, and kept
    EXPECT_EQ(m.triangles[1][0], m.triangles[0][0]);
}

TEST(LoadOptions, WeldMergesIdenticalPositions) {
    // Two triangles sharing an edge, written with separate vertices.
    const std::string text = "OFF\n6 2 0\n0 0 0\n1 0 0\n0 1 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 3 4 5\n";
    const auto path = write_file("io_load", "unwelded.off", text);
    LoadReport report;
    EXPECT_EQ(load_mesh(path, {}, &report).vertex_count(), 6u);
    EXPECT_FALSE(report.welded);
    const Mesh welded = load_mesh(path, LoadOptions{.weld = true}, &report);
    EXPECT_EQ(welded.vertex_count(), 4u);
    EXPECT_EQ(welded.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {1, 3, 2}}));
    EXPECT_TRUE(report.welded);
    EXPECT_EQ(report.welded_vertices, 2u);
    EXPECT_EQ(report.file_vertices, 6u);
}

TEST(LoadErrors, MessagesNameTheFile) {
    const auto path = write_file("io_load", "broken.off", "OFF\n4 4 0\n0 0 0\n");
    try {
        load_mesh(path);
        FAIL() << "no error";
    } catch (const gimg::geo::InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": ", 0), 0u) << e.what();
    }
}
