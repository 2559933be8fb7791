// libFuzzer target over the readers of a cylindrical geometry image's files (what `gimg
// reconstruct` reads): the EXR reader and the frame.json reader, and the check that the two belong
// together. The first byte picks the file (even: distance.exr, odd: frame.json; the seeds use '0'
// and '1'), the rest is its contents; the other file of the pair is a valid one written at start.
//
// Beyond crashes, hangs and memory errors, it checks what the readers promise: an image or a
// geo::InputError, never anything else; a read image holds d in [-1, 1] where covered, and a read
// frame a rotation and a positive scale.

#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"
#include "gimg/passes/cylinder.h"

#include <glm/matrix.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "gimg fuzz: %s\n", what.c_str());
    std::abort();
}

fs::path folder(const char* which) {
    static const fs::path root = fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    return root / ("gimg-fuzz-images-" + std::to_string(::getpid()) + "-" + which);
}

void remove_folders() {
    std::error_code ec;
    fs::remove_all(folder("exr"), ec);
    fs::remove_all(folder("frame"), ec);
}

// A valid pair in each folder: the fuzzed file replaces one of them.
void write_valid_pairs() {
    gimg::passes::CylinderImage image(8, 4);
    for (std::size_t i = 0; i < image.covered.size(); ++i) {
        image.covered[i] = i % 3 != 0;
        image.distance[i] = 0.25f;
    }
    for (const char* which : {"exr", "frame"})
        gimg::passes::write_cylinder_files(folder(which), image, gimg::passes::CylinderFrame{}, {"fuzz", "fuzz"});
    std::atexit(remove_folders);
}

void check(const gimg::passes::CylinderFiles& files) {
    const auto& image = files.image;
    if (image.covered.size() != std::size_t(image.width) * image.height ||
        image.distance.size() != image.covered.size())
        bug("an image whose arrays do not match its size");
    for (std::size_t i = 0; i < image.covered.size(); ++i)
        if (image.covered[i] && !(std::abs(image.distance[i]) <= 1.0f)) bug("a covered pixel with d outside [-1, 1]");
    if (!(files.frame.scale > 0.0) || !std::isfinite(files.frame.scale)) bug("a frame without a positive scale");
    if (!(std::abs(glm::determinant(files.frame.rotation) - 1.0) < 1e-6)) bug("a frame whose rotation is not one");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool ready = (write_valid_pairs(), true);
    (void)ready;
    if (size == 0) return 0;
    const bool exr = data[0] % 2 == 0;
    const fs::path dir = folder(exr ? "exr" : "frame");
    {
        std::ofstream out(dir / (exr ? "distance.exr" : "frame.json"), std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    }
    try {
        if (exr) (void)gimg::geo::read_exr(dir / "distance.exr");
        check(gimg::passes::read_cylinder_files(dir / "distance.exr"));
    } catch (const gimg::geo::InputError&) {
        return 0;  // a clear refusal
    } catch (const std::exception& e) {
        bug(std::string("a reader threw something other than InputError: ") + e.what());
    }
    return 0;
}
