// Load every format, save as binary PLY, ascii PLY and OBJ, load again: the same positions (bit
// for bit: both sides are float32) and the same triangles. And saving never half-writes.
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"

#include "mesh_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using gimg::geo::load_mesh;
using gimg::geo::LoadReport;
using gimg::geo::Mesh;
using gimg::geo::save_mesh;
using gimg::geo::SaveOptions;

namespace {

struct Target {
    const char* extension;
    bool binary;
};
constexpr Target kTargets[] = {{".ply", true}, {".ply", false}, {".obj", false}};

void expect_same_mesh(const Mesh& a, const Mesh& b, const std::string& what) {
    EXPECT_EQ(a.positions, b.positions) << what;
    EXPECT_EQ(a.triangles, b.triangles) << what;
    EXPECT_EQ(a.has_texcoords(), b.has_texcoords()) << what;
    if (a.has_texcoords() && b.has_texcoords()) {
        EXPECT_EQ(a.texcoords, b.texcoords) << what;
    }
}

void round_trip(const std::filesystem::path& source) {
    const Mesh original = load_mesh(source);
    ASSERT_GT(original.face_count(), 0u);
    for (const Target& target : kTargets) {
        const std::string name = source.stem().string() + "_" + source.extension().string().substr(1) +
                                 (target.binary ? "_binary" : "_ascii") + target.extension;
        const auto saved = gimg::test::output_dir("io_roundtrip") / name;
        save_mesh(original, saved, SaveOptions{.binary = target.binary});
        LoadReport report;
        const Mesh reloaded = load_mesh(saved, {}, &report);
        expect_same_mesh(original, reloaded, name);
        EXPECT_EQ(report.encoding, target.binary ? "binary_little_endian" : "ascii") << name;
    }
}

}  // namespace

TEST(RoundTrip, EverySeedFormat) {
    for (const char* name : {"tetra.off", "tetra_colors.off", "tetra_ascii.ply", "tetra_binary.ply", "cube_quads.obj",
                             "tetra_ascii.stl", "tetra_binary.stl"}) {
        SCOPED_TRACE(name);
        round_trip(gimg::test::seed_mesh(name));
    }
}

TEST(RoundTrip, ValuesFloatsMustKeep) {
    // Values whose shortest decimal form is long, tiny and huge floats, negative zero.
    Mesh m;
    m.positions = {{0.1f, -1.0f / 3.0f, 3.4e38f}, {1e-38f, -0.0f, 123456.789f}, {2.5e-45f, 7.0f, -8.125f}};
    m.triangles = {{0, 1, 2}, {0, 2, 1}, {1, 1, 2}};  // a duplicate face reversed and a collapsed face
    m.texcoords = {{0.25, 0.75}, {1.0f / 7.0f, 0}, {1, 1}};
    for (const Target& target : kTargets) {
        const auto path = gimg::test::output_dir("io_roundtrip") /
                          (std::string("values") + (target.binary ? "_binary" : "_ascii") + target.extension);
        save_mesh(m, path, SaveOptions{.binary = target.binary});
        const Mesh back = load_mesh(path);
        expect_same_mesh(m, back, path.string());
        EXPECT_TRUE(std::signbit(back.positions[1].y)) << path;
    }
}

TEST(RoundTrip, SharedMeshesOfEachFormat) {
    for (const char* name : {"bunny_small.obj", "dragon_res4.ply", "nefertiti.off"}) {
        auto path = gimg::test::shared_mesh(name);
        if (!path) GTEST_SKIP() << "shared mesh " << name << " not found (set GIMG_MESH_DIR)";
        SCOPED_TRACE(name);
        round_trip(*path);
    }
}

TEST(SaveMesh, FailuresLeaveNothingHalfWritten) {
    const auto dir = gimg::test::output_dir("io_save");
    const auto existing = gimg::test::write_file("io_save", "existing.ply", "old contents");
    Mesh bad;
    bad.positions = {{0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}};
    bad.triangles = {{0, 1, 2}};
    EXPECT_THROW(save_mesh(bad, existing), gimg::geo::InputError);
    EXPECT_EQ(gimg::test::read_file(existing), "old contents");

    Mesh out_of_range;
    out_of_range.positions = {{0, 0, 0}};
    out_of_range.triangles = {{0, 0, 5}};
    EXPECT_THROW(save_mesh(out_of_range, dir / "range.obj"), gimg::geo::InputError);
    EXPECT_FALSE(std::filesystem::exists(dir / "range.obj"));

    const Mesh good = load_mesh(gimg::test::seed_mesh("tetra.off"));
    EXPECT_THROW(save_mesh(good, dir / "no_such_folder" / "x.ply"), gimg::geo::InputError);
    EXPECT_THROW(save_mesh(good, dir / "x.stl"), gimg::geo::InputError);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.stl"));

    // Nothing but the files written on purpose: no temporary left behind.
    save_mesh(good, dir / "good.ply");
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
    }
}

TEST(RoundTrip, NormalsAreWrittenAndTheRestReadsBack) {
    gimg::geo::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    for (const char* name : {"normals.ply", "normals_ascii.ply", "normals.obj"}) {
        const auto path = gimg::test::output_dir("io") / name;
        gimg::geo::save_mesh(m, path, {.binary = std::string(name) == "normals.ply"});
        std::ifstream in(path, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        EXPECT_NE(text.find(std::string(name).ends_with(".obj") ? "vn 0 0 1" : "property float nx"), std::string::npos)
            << name;
        const gimg::geo::Mesh back = gimg::geo::load_mesh(path);
        EXPECT_EQ(back.positions, m.positions) << name;
        EXPECT_EQ(back.triangles, m.triangles) << name;
    }
}

// Float64 files hold every bit of the doubles (float32 would round 1 + 1e-15 to 1). gimg's own
// loader reads positions as float32, so a reload gives the rounded values.
TEST(RoundTrip, DoublePrecisionFilesHoldTheDoubles) {
    Mesh mesh;
    mesh.positions = {{1.0, 1e-12, 0.0}, {1.0 + 1e-15, 2e-12, 1e-13}, {0.1, 0.2, 0.3}};
    mesh.triangles = {{0, 1, 2}};
    for (const Target& target : kTargets) {
        const auto path = gimg::test::output_dir("io_roundtrip") /
                          (std::string("double") + (target.binary ? "_binary" : "_ascii") + target.extension);
        save_mesh(mesh, path, SaveOptions{.binary = target.binary, .double_precision = true});
        std::ifstream in(path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::vector<double> values;
        if (target.binary) {
            const std::size_t body = bytes.find("end_header\n") + 11;
            ASSERT_NE(bytes.find("property double x"), std::string::npos);
            for (std::size_t k = 0; k < 9; ++k) {
                double v;
                std::memcpy(&v, bytes.data() + body + 8 * k, 8);
                values.push_back(v);
            }
        } else {
            std::istringstream text(
                bytes.substr(target.extension == std::string(".obj") ? 0 : bytes.find("end_header\n") + 11));
            std::string line;
            while (values.size() < 9 && std::getline(text, line)) {
                if (line.empty() || line[0] == '#') continue;
                std::istringstream fields(line[0] == 'v' ? line.substr(1) : line);
                double v;
                while (fields >> v) values.push_back(v);
            }
        }
        ASSERT_EQ(values.size(), 9u) << path;
        for (std::size_t k = 0; k < 9; ++k)
            EXPECT_EQ(values[k], mesh.positions[k / 3][int(k % 3)]) << path << " value " << k;
        const Mesh back = load_mesh(path);
        ASSERT_EQ(back.vertex_count(), 3u) << path;
        EXPECT_EQ(back.positions[1].x, double(float(1.0 + 1e-15))) << path;
    }
}

// Texture coordinates follow the precision asked for: float64 keeps every bit (a map's triangles
// can be below float32's resolution), float32 rounds them; the OBJ's vt lines and the PLY's s, t.
TEST(RoundTrip, DoublePrecisionFilesHoldTheTextureCoordinates) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.texcoords = {{0.5 + 1e-12, 0.25}, {1.0 - 1e-13, 1e-14}, {0.1, 0.7}};
    for (const bool dbl : {true, false}) {
        for (const Target& target : kTargets) {
            const auto path =
                gimg::test::output_dir("io_roundtrip") / (std::string("uv_") + (dbl ? "double" : "float") +
                                                          (target.binary ? "_binary" : "_ascii") + target.extension);
            save_mesh(mesh, path, SaveOptions{.binary = target.binary, .double_precision = dbl});
            std::ifstream in(path, std::ios::binary);
            const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            std::vector<double> uv;  // as written
            if (target.binary) {
                const std::size_t body = bytes.find("end_header\n") + 11, real = dbl ? 8 : 4;
                for (std::size_t v = 0; v < 3; ++v)
                    for (std::size_t k = 0; k < 2; ++k) {
                        const char* at = bytes.data() + body + (5 * v + 3 + k) * real;
                        if (dbl) {
                            double x;
                            std::memcpy(&x, at, 8);
                            uv.push_back(x);
                        } else {
                            float x;
                            std::memcpy(&x, at, 4);
                            uv.push_back(x);
                        }
                    }
            } else {
                std::istringstream text(
                    target.extension == std::string(".obj") ? bytes : bytes.substr(bytes.find("end_header\n") + 11));
                std::string line;
                for (int v = 0; v < 3 && std::getline(text, line);) {
                    std::istringstream fields(line);
                    std::string head;
                    if (target.extension == std::string(".obj")) {
                        fields >> head;
                        if (head != "vt") continue;
                    } else {
                        double skip;
                        for (int k = 0; k < 3; ++k) fields >> skip;  // x, y, z
                    }
                    double s, t;
                    fields >> s >> t;
                    uv.push_back(s);
                    uv.push_back(t);
                    ++v;
                }
            }
            ASSERT_EQ(uv.size(), 6u) << path;
            for (std::size_t k = 0; k < 6; ++k) {
                const double want = mesh.texcoords[k / 2][int(k % 2)];
                if (dbl)
                    EXPECT_EQ(uv[k], want) << path << " value " << k;
                else  // text holds the shortest float, which reads back as that float
                    EXPECT_EQ(float(uv[k]), float(want)) << path << " value " << k;
            }
        }
    }
}
