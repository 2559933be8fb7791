// Writes the hostile inputs tests/hostile/hostile.sh feeds to gimg, at test time (no large files
// in the tree):
//   make_hostile_files copies N FILE.off          N copies of one triangle
//   make_hostile_files scaled S FILE.off          an icosphere S across
//   make_hostile_files stray FILE.off             an icosphere and one unused vertex 1e6 away
//   make_hostile_files flat FILE.off              100 faces of zero area
//   make_hostile_files image KIND DIR             DIR/distance.exr and DIR/frame.json, where KIND is
//       good, empty (no pixel covered), checker (no 2x2 block covered), nan-mask, no-mask,
//       window (data window smaller than the display window) or zero-rotation
#include "gimg/geometry/exr.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

namespace gp = gimg::passes;
namespace geo = gimg::geo;

namespace {

void write_off(const geo::Mesh& m, const std::string& path) {
    std::ofstream out(path);
    out.precision(17);
    out << "OFF\n" << m.positions.size() << " " << m.triangles.size() << " 0\n";
    for (const auto& p : m.positions) out << p.x << " " << p.y << " " << p.z << "\n";
    for (const auto& t : m.triangles) out << "3 " << t.x << " " << t.y << " " << t.z << "\n";
}

gp::CylinderImage sphere_image() {
    const geo::Mesh s = geo::make_icosphere(0.4, 3);
    return gp::cylinder_raycast(gp::make_cylinder_mesh(s, gp::fit_cylinder_frame(s)), 32, 16);
}

void write_image(const std::string& kind, const std::string& dir) {
    gp::CylinderImage image = sphere_image();
    const gp::CylinderFrame frame;
    if (kind == "empty") std::fill(image.covered.begin(), image.covered.end(), 0);
    if (kind == "checker")
        for (std::uint32_t v = 0; v < image.height; ++v)
            for (std::uint32_t u = 0; u < image.width; ++u) image.covered[image.index(u, v)] = (u + v) % 2;
    gp::write_cylinder_files(dir, image, frame, {"make_hostile_files", "raycast"});
    if (kind == "good" || kind == "empty" || kind == "checker") return;
    if (kind == "zero-rotation") {
        std::ifstream in(dir + "/frame.json");
        nlohmann::json j = nlohmann::json::parse(in);
        j["rotation"] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        std::ofstream(dir + "/frame.json") << j.dump(2);
        return;
    }
    // The EXR written by hand: gimg's writer would not make these.
    const int w = int(image.width), h = int(image.height);
    std::vector<float> d(image.distance), mask(image.covered.begin(), image.covered.end());
    if (kind == "nan-mask") mask[5] = std::numeric_limits<float>::quiet_NaN();
    Imf::Header header(w, h);
    if (kind == "window") header.dataWindow() = Imath::Box2i({0, 0}, {w - 1, h / 2 - 1});
    Imf::FrameBuffer fb;
    header.channels().insert("d", Imf::Channel(Imf::FLOAT));
    fb.insert("d", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(d.data()), 4, 4 * std::size_t(w)));
    if (kind != "no-mask") {
        header.channels().insert("mask", Imf::Channel(Imf::FLOAT));
        fb.insert("mask", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(mask.data()), 4, 4 * std::size_t(w)));
    }
    Imf::OutputFile file((dir + "/distance.exr").c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(kind == "window" ? h / 2 : h);
}

}  // namespace

int main(int argc, char** argv) {
    const std::string what = argc > 1 ? argv[1] : "";
    if (what == "copies" && argc == 4) {
        geo::Mesh m;
        m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        m.triangles.assign(std::stoul(argv[2]), {0, 1, 2});
        write_off(m, argv[3]);
    } else if (what == "scaled" && argc == 4) {
        geo::Mesh m = geo::make_icosphere(0.5 * std::stod(argv[2]), 3);
        write_off(m, argv[3]);
    } else if (what == "stray" && argc == 3) {
        geo::Mesh m = geo::make_icosphere(0.5, 3);
        m.positions.push_back({1e6, 0, 0});
        write_off(m, argv[2]);
    } else if (what == "flat" && argc == 3) {
        geo::Mesh m;
        for (int i = 0; i < 100; ++i) {
            for (int k = 0; k < 3; ++k) m.positions.push_back({double(i), double(i % 7), 0});
            m.triangles.push_back({std::uint32_t(3 * i), std::uint32_t(3 * i + 1), std::uint32_t(3 * i + 2)});
        }
        write_off(m, argv[2]);
    } else if (what == "image" && argc == 4) {
        write_image(argv[2], argv[3]);
    } else {
        std::fprintf(stderr, "make_hostile_files: unknown request (see the comment at the top)\n");
        return 2;
    }
    return 0;
}
