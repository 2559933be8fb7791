// load_mesh: read the file, validate it (io_scan_*.cpp), let OpenMesh read the validated bytes
// (io_openmesh_read.cpp), put back the faces OpenMesh's readers drop, triangulate, weld on request.

#include "gimg/geometry/io.h"

#include "io_openmesh_read.h"
#include "io_scan.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/weld.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>

namespace gimg::geo {

namespace {

std::string format_of(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl") return ext.substr(1);
    if (ext.empty())
        throw InputError("no file extension: cannot tell the mesh format (gimg reads .obj, .ply, .off, .stl)");
    throw InputError("unknown mesh format '" + ext + "' (gimg reads .obj, .ply, .off, .stl)");
}

std::string read_whole_file(const std::filesystem::path& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw InputError("no such file");
    if (std::filesystem::is_directory(status)) throw InputError("is a directory, not a mesh file");
    // A FIFO or device (/dev/zero) could block or never end.
    if (!std::filesystem::is_regular_file(status)) throw InputError("not a regular file");
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError("cannot read the file size: " + ec.message());
    if (size == 0) throw InputError("the file is empty");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(std::string("cannot open the file: ") + std::strerror(errno));
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<std::size_t>(in.gcount()));  // the file may have shrunk meanwhile
    if (bytes.empty()) throw InputError("the file is empty");
    return bytes;
}

io::ScanResult scan(const std::string& format, std::string_view bytes) {
    if (format == "off") return io::scan_off(bytes);
    if (format == "ply") return io::scan_ply(bytes);
    if (format == "obj") return io::scan_obj(bytes);
    return io::scan_stl(bytes);
}

// Polygons in file order: the reader's, with the faces it altered or dropped as the file has them.
void collect_faces(const io::ScanResult& scan, const io::RawMesh& raw, std::vector<std::uint32_t>& offsets,
                   std::vector<std::uint32_t>& indices) {
    offsets.assign(1, 0);
    indices.clear();
    indices.reserve(raw.face_indices.size() + 3 * scan.kept_faces.size());
    std::size_t next_raw = 0, next_kept = 0;
    auto take_raw = [&](bool keep) {
        if (next_raw >= raw.face_count()) throw io::ReaderMismatch("OpenMesh's reader handed over too few faces");
        if (keep) {
            indices.insert(indices.end(), raw.face_indices.begin() + raw.face_offsets[next_raw],
                           raw.face_indices.begin() + raw.face_offsets[next_raw + 1]);
        }
        ++next_raw;
    };
    for (std::size_t f = 0; f < scan.faces; ++f) {
        if (next_kept < scan.kept_faces.size() && scan.kept_faces[next_kept].file_index == f) {
            const io::KeptFace& kept = scan.kept_faces[next_kept++];
            if (kept.reader_delivers) take_raw(false);
            indices.insert(indices.end(), kept.indices.begin(), kept.indices.end());
        } else {
            take_raw(true);
        }
        offsets.push_back(static_cast<std::uint32_t>(indices.size()));
    }
}

Mesh build_mesh(const io::ScanResult& scan, const io::RawMesh& raw, LoadReport& report) {
    std::vector<std::uint32_t> offsets, indices;
    collect_faces(scan, raw, offsets, indices);
    Mesh mesh;
    mesh.positions.reserve(raw.positions.size());
    for (const glm::vec3& p : raw.positions) mesh.positions.emplace_back(p);
    mesh.triangles.reserve(indices.size());
    for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
        const std::uint32_t* c = indices.data() + offsets[f];
        const std::uint32_t corners = offsets[f + 1] - offsets[f];
        // A fan from the first corner: exact for convex polygons, which is what files hold.
        for (std::uint32_t k = 1; k + 1 < corners; ++k) mesh.triangles.emplace_back(c[0], c[k], c[k + 1]);
        if (corners > 3) ++report.polygons_triangulated;
    }
    if (scan.has_texcoords) {
        std::size_t missing = 0;
        mesh.texcoords.reserve(raw.texcoords.size());
        for (std::size_t i = 0; i < raw.texcoords.size(); ++i) {
            mesh.texcoords.emplace_back(raw.texcoords[i]);
            if (!raw.texcoord_set[i]) ++missing;
        }
        if (missing > 0) {
            report.notes.push_back(std::to_string(missing) + " vertices have no texture coordinate (set to 0,0)");
        }
        if (raw.texcoord_conflicts > 0) {
            report.notes.push_back(std::to_string(raw.texcoord_conflicts) +
                                   " vertices have two texture coordinates (seams); the last one is kept");
        }
    }
    report.texcoord_conflicts = raw.texcoord_conflicts;
    return mesh;
}

}  // namespace

Mesh load_mesh(const std::filesystem::path& path, const LoadOptions& options, LoadReport* report) {
    LoadReport local;
    LoadReport& r = report ? *report : local;
    r = LoadReport{};
    try {
        const std::string format = format_of(path);
        const std::string bytes = read_whole_file(path);
        const io::ScanResult scanned = scan(format, bytes);
        const io::RawMesh raw = io::read_with_openmesh(scanned);
        r.format = scanned.format;
        r.encoding = scanned.encoding;
        r.file_vertices = scanned.vertices;
        r.file_faces = scanned.faces;
        r.notes = scanned.notes;
        Mesh mesh = build_mesh(scanned, raw, r);
        if (format == "stl") {
            r.file_vertices = 3 * scanned.faces;
            r.welded = true;
            r.welded_vertices = r.file_vertices - mesh.vertex_count();
            r.notes.push_back(
                "STL stores each facet's corners apart: OpenMesh's reader merged corners at the same "
                "position (" +
                std::to_string(r.file_vertices) + " corners, " + std::to_string(mesh.vertex_count()) + " vertices)");
        }
        if (options.weld) {
            const std::size_t removed = weld_identical_vertices(mesh);
            r.welded = true;
            r.welded_vertices += removed;
            r.notes.push_back("welding merged " + std::to_string(removed) + " vertices at identical positions");
        }
        return mesh;
    } catch (const io::ReaderMismatch& e) {
        throw io::ReaderMismatch(path.string() + ": " + e.what());
    } catch (const InputError& e) {
        throw InputError(path.string() + ": " + e.what());
    }
}

}  // namespace gimg::geo
