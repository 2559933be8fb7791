// The real meshes of ../shared/meshes: every file INDEX.tsv lists must load with exactly its
// vertex and face counts, and the topology groups of the folder's README must hold. Skips with a
// message when the folder is absent.
#include "gimg/geometry/io.h"
#include "gimg/geometry/topology.h"

#include "test_data.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using gimg::geo::LoadReport;
using gimg::geo::MeshInfo;

namespace {

struct IndexRow {
    std::string file;
    std::size_t vertices = 0;
    std::size_t faces = 0;
};

std::vector<IndexRow> read_index(const std::filesystem::path& dir) {
    std::ifstream in(dir / "INDEX.tsv");
    std::vector<IndexRow> rows;
    std::string line;
    std::getline(in, line);  // header: file V F bytes
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        IndexRow row;
        if (std::getline(fields, row.file, '\t') && fields >> row.vertices >> row.faces) rows.push_back(row);
    }
    return rows;
}

// Loads `path` and checks it against its INDEX.tsv row; INDEX counts polygons as faces.
void expect_index_counts(const std::filesystem::path& path, const IndexRow& row) {
    LoadReport report;
    const gimg::geo::Mesh mesh = gimg::geo::load_mesh(path, {}, &report);
    EXPECT_EQ(mesh.vertex_count(), row.vertices) << row.file;
    EXPECT_EQ(report.file_vertices, row.vertices) << row.file;
    EXPECT_EQ(report.file_faces, row.faces) << row.file;
    if (report.polygons_triangulated == 0) {
        EXPECT_EQ(mesh.face_count(), row.faces) << row.file;
    }
    EXPECT_GE(mesh.face_count(), row.faces) << row.file;
}

// The README's topology table: what each mesh must be.
struct Expected {
    const char* file;
    std::size_t components;
    std::optional<long long> genus;    // of the one component (when components == 1)
    std::optional<std::size_t> loops;  // boundary loops
    bool manifold;
};

const Expected kReadme[] = {
    // closed, genus 0, manifold, one piece
    {"hand.off", 1, 0, 0, true},
    {"bunny_small.obj", 1, 0, 0, true},
    {"blobby.off", 1, 0, 0, true},
    {"triceratops.off", 1, 0, 0, true},
    {"cow.off", 1, 0, 0, true},
    {"dino.off", 1, 0, 0, true},
    {"homer.off", 1, 0, 0, true},
    {"fandisk.off", 1, 0, 0, true},
    {"camel.off", 1, 0, 0, true},
    {"armadillo.off", 1, 0, 0, true},
    {"bunny.off", 1, 0, 0, true},
    // closed, genus > 0
    {"eight.off", 1, 2, 0, true},
    {"elk.off", 1, 1, 0, true},
    {"couplingdown.off", 1, 9, 0, true},
    {"elephant.off", 1, 3, 0, true},
    {"knot1.off", 1, 1, 0, true},
    {"anchor_dense.off", 1, 4, 0, true},
    {"femur.off", 1, 2, 0, true},
    {"cheese.off", 1, 133, 0, true},
    {"turbine.off", 1, 11, 0, true},
    // disk: one boundary loop
    {"nefertiti.off", 1, 0, 1, true},
    {"terrain.obj", 1, 0, 1, true},
    {"three_peaks.off", 1, 0, 1, true},
    {"mushroom.off", 1, 0, 1, true},
    {"mannequin_devil.off", 1, 0, 1, true},
    // open, several holes
    {"pig.off", 1, 0, 7, true},
    {"head.off", 1, 0, 3, true},
    {"holes.off", 1, 0, 7, true},
    {"mech_holes_shark.off", 1, 0, 4, true},
    {"chinese_dragon_10k.off", 1, 0, 2, true},
    {"aneurysm.obj", 1, 0, 3, true},
    {"elephant_with_holes.off", 1, 3, 106, true},
    // messy real data (the defects are checked below)
    {"teapot.obj", 32, std::nullopt, std::nullopt, true},
    {"snowden.obj", 4, std::nullopt, std::nullopt, false},
    {"snowden_lo.obj", 4, std::nullopt, std::nullopt, false},
    {"dragon_res3.ply", 1, std::nullopt, std::nullopt, false},
    {"dragon_res4.ply", 1, std::nullopt, std::nullopt, false},
};

}  // namespace

TEST(SharedMeshes, CountsMatchIndex) {
    const auto dir = gimg::test::mesh_dir();
    if (!dir) GTEST_SKIP() << "shared mesh folder not found (set GIMG_MESH_DIR)";
    const std::vector<IndexRow> rows = read_index(*dir);
    ASSERT_GT(rows.size(), 30u) << "INDEX.tsv unreadable";
    std::size_t checked = 0;
    for (const IndexRow& row : rows) {
        const auto path = *dir / row.file;
        if (!std::filesystem::exists(path)) continue;  // shape_db/...: inside the archive
        expect_index_counts(path, row);
        ++checked;
    }
    EXPECT_GE(checked, 37u);
}

TEST(SharedMeshes, ReadmeTopologyGroups) {
    std::size_t checked = 0;
    for (const Expected& e : kReadme) {
        const auto path = gimg::test::shared_mesh(e.file);
        if (!path) continue;
        SCOPED_TRACE(e.file);
        const MeshInfo info = gimg::geo::analyze_topology(gimg::geo::load_mesh(*path));
        EXPECT_EQ(info.components, e.components);
        EXPECT_EQ(info.manifold, e.manifold);
        if (e.loops) {
            EXPECT_EQ(info.boundary_loops, *e.loops);
        }
        if (e.genus) {
            ASSERT_EQ(info.component_info.size(), 1u);
            EXPECT_EQ(info.component_info[0].genus, *e.genus);
        }
        if (e.genus && e.loops && *e.loops == 0) {
            EXPECT_TRUE(info.closed);
        }
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << "shared mesh folder not found (set GIMG_MESH_DIR)";
}

TEST(SharedMeshes, MessyDefectsAreReported) {
    const auto teapot = gimg::test::shared_mesh("teapot.obj");
    const auto snowden = gimg::test::shared_mesh("snowden_lo.obj");
    const auto dragon = gimg::test::shared_mesh("dragon_res4.ply");
    if (!teapot || !snowden || !dragon) GTEST_SKIP() << "shared meshes not found (set GIMG_MESH_DIR)";

    // 32 unwelded patches: each an open piece; welding joins them.
    const MeshInfo patches = gimg::geo::analyze_topology(gimg::geo::load_mesh(*teapot));
    EXPECT_EQ(patches.boundary_loops, 32u);
    LoadReport report;
    const MeshInfo welded = gimg::geo::analyze_topology(gimg::geo::load_mesh(*teapot, {.weld = true}, &report));
    EXPECT_GT(report.welded_vertices, 0u);
    EXPECT_LT(welded.components, patches.components);

    const MeshInfo s = gimg::geo::analyze_topology(gimg::geo::load_mesh(*snowden));
    EXPECT_GT(s.non_manifold_edges, 0u);

    const MeshInfo d = gimg::geo::analyze_topology(gimg::geo::load_mesh(*dragon));
    EXPECT_GT(d.non_manifold_edges, 0u);
    EXPECT_GT(d.duplicate_faces, 0u);
    EXPECT_GT(d.isolated_vertices, 0u);  // INDEX counts them: V includes vertices in no face
}

// shape_db.tar.xz: 99 polygon soups, unpacked into the test output folder.
TEST(SharedMeshes, ShapeDbCountsMatchIndex) {
    const auto archive = gimg::test::shared_mesh("shape_db.tar.xz");
    if (!archive) GTEST_SKIP() << "shape_db.tar.xz not found (set GIMG_MESH_DIR)";
    const auto target = gimg::test::output_dir("shape_db");
    const std::string command = "tar -xJf '" + archive->string() + "' -C '" + target.string() + "'";
    if (std::system(command.c_str()) != 0) GTEST_SKIP() << "could not unpack shape_db.tar.xz with tar";
    std::size_t checked = 0;
    for (const IndexRow& row : read_index(*gimg::test::mesh_dir())) {
        if (row.file.rfind("shape_db/", 0) != 0) continue;
        expect_index_counts(target / row.file, row);
        ++checked;
    }
    EXPECT_EQ(checked, 99u);
}
