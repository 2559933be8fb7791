// libFuzzer target over gimg's mesh loaders. The first byte picks the format (its value modulo 4:
// 0 OFF, 1 PLY, 2 OBJ, 3 STL; the seed corpus uses the characters '0'..'3'), the rest is the file.
//
// Beyond crashes, hangs and memory errors (ASan, UBSan, libFuzzer's -timeout and -rss_limit_mb),
// it checks what load_mesh promises: it returns a usable mesh or throws InputError, never anything
// else; OpenMesh's reader never disagrees with gimg's validation (ReaderMismatch: the validation
// let through something the reader reads differently); the mesh is analysable and survives a
// save/load round trip unchanged.

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/topology.h"

#include "io_openmesh_read.h"  // ReaderMismatch (geometry/src)

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "gimg fuzz: %s\n", what.c_str());
    std::abort();
}

const char* const kExtensions[] = {".off", ".ply", ".obj", ".stl"};

std::filesystem::path scratch(const char* extension) {
    static const std::filesystem::path dir = std::filesystem::exists("/dev/shm")
                                                 ? std::filesystem::path("/dev/shm")
                                                 : std::filesystem::temp_directory_path();
    return dir / ("gimg-fuzz-" + std::to_string(::getpid()) + extension);
}

// libFuzzer ends with exit() when its time is up: remove this process's scratch files then.
void remove_scratch_files() {
    std::error_code ec;
    for (const char* extension : kExtensions) std::filesystem::remove(scratch(extension), ec);
}

void check_mesh(const gimg::geo::Mesh& mesh) {
    if (mesh.face_count() == 0) bug("a mesh without faces loaded");
    for (const glm::uvec3& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= mesh.vertex_count()) bug("a triangle names a missing vertex");
        }
    }
    for (const glm::dvec3& p : mesh.positions) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) bug("a non-finite position loaded");
    }
    if (!mesh.texcoords.empty() && mesh.texcoords.size() != mesh.vertex_count()) bug("texcoords of the wrong size");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)scratch("");  // create its static folder first, so that it is destroyed after the handler runs
    std::atexit(remove_scratch_files);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::filesystem::path input = scratch(kExtensions[data[0] % 4]);
    {
        std::ofstream out(input, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    }
    gimg::geo::Mesh mesh;
    try {
        mesh = gimg::geo::load_mesh(input);
    } catch (const gimg::geo::io::ReaderMismatch& e) {
        bug(std::string("validation and OpenMesh disagree: ") + e.what());
    } catch (const gimg::geo::InputError&) {
        return 0;  // a clear refusal is the right answer to most inputs
    } catch (const std::exception& e) {
        bug(std::string("load_mesh threw something other than InputError: ") + e.what());
    }
    check_mesh(mesh);
    (void)gimg::geo::analyze_topology(mesh);

    // Written files read back the same (positions are float on both sides).
    const std::filesystem::path saved = scratch(".ply");
    try {
        gimg::geo::save_mesh(mesh, saved);
        const gimg::geo::Mesh back = gimg::geo::load_mesh(saved);
        if (back.positions != mesh.positions || back.triangles != mesh.triangles)
            bug("a PLY round trip changed the mesh");
    } catch (const std::exception& e) {
        bug(std::string("saving or reloading a loaded mesh failed: ") + e.what());
    }
    return 0;
}
