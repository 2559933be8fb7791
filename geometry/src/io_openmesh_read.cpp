#include "io_openmesh_read.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/OBJReader.hh>
#include <OpenMesh/Core/IO/reader/OFFReader.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/IO/reader/STLReader.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <streambuf>
#include <string>
#include <unistd.h>

namespace gimg::geo::io {

namespace {

namespace OM = OpenMesh;
using OM::IO::BaseImporter;

[[noreturn]] void mismatch(const std::string& what) {
    throw ReaderMismatch("OpenMesh's reader and gimg's validation disagree on this file: " + what +
                         " (an unsupported variant of the format)");
}

// Records what a reader hands over. Only what gimg keeps (positions, polygons, per-vertex texture
// coordinates) is stored; everything else is ignored. It refuses more vertices or faces than the
// scan counted and indices out of range, so that a reader misreading a file stops at once
// instead of running on.
class RecordingImporter final : public BaseImporter {
public:
    RecordingImporter(RawMesh& out, const ScanResult& scan) : out_(out), scan_(scan) {
        out_.positions.reserve(scan.vertices);
        out_.face_offsets.reserve(scan.reader_faces + 1);
        out_.face_indices.reserve(3 * scan.reader_faces);
        if (scan.has_texcoords) {
            out_.texcoords.assign(scan.vertices, glm::vec2(0.0f));
            out_.texcoord_set.assign(scan.vertices, 0);
        }
    }

    OM::VertexHandle add_vertex(const OM::Vec3f& p) override {
        if (out_.positions.size() >= scan_.vertices) {
            mismatch("more than the " + std::to_string(scan_.vertices) + " vertices counted");
        }
        out_.positions.emplace_back(p[0], p[1], p[2]);
        return OM::VertexHandle(static_cast<int>(out_.positions.size() - 1));
    }
    OM::VertexHandle add_vertex() override { return add_vertex(OM::Vec3f(0.0f, 0.0f, 0.0f)); }
    void set_point(OM::VertexHandle v, const OM::Vec3f& p) override {
        if (valid(v)) out_.positions[static_cast<std::size_t>(v.idx())] = glm::vec3(p[0], p[1], p[2]);
    }

    OM::FaceHandle add_face(const VHandles& corners) override {
        if (out_.face_count() >= scan_.reader_faces) {
            mismatch("more than the " + std::to_string(scan_.reader_faces) + " faces counted");
        }
        if (corners.size() < 3) mismatch("a face of " + std::to_string(corners.size()) + " vertices");
        for (const OM::VertexHandle& v : corners) {
            if (!valid(v)) mismatch("a face names vertex " + std::to_string(v.idx()));
            out_.face_indices.push_back(static_cast<std::uint32_t>(v.idx()));
        }
        out_.face_offsets.push_back(static_cast<std::uint32_t>(out_.face_indices.size()));
        return OM::FaceHandle(static_cast<int>(out_.face_count() - 1));
    }

    void set_texcoord(OM::VertexHandle v, const OM::Vec2f& t) override { record_texcoord(v, t[0], t[1]); }
    void set_texcoord(OM::VertexHandle v, const OM::Vec3f& t) override { record_texcoord(v, t[0], t[1]); }

    std::size_t n_vertices() const override { return out_.positions.size(); }
    std::size_t n_faces() const override { return out_.face_count(); }
    std::size_t n_edges() const override { return 0; }

    // What gimg does not keep.
    OM::HalfedgeHandle add_edge(OM::VertexHandle, OM::VertexHandle) override { return OM::HalfedgeHandle(); }
    OM::FaceHandle add_face(OM::HalfedgeHandle) override { return OM::FaceHandle(); }
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec2f>&) override {}
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle, const std::vector<OM::Vec3f>&) override {}
    void set_face_texindex(OM::FaceHandle, int) override {}
    void set_halfedge(OM::VertexHandle, OM::HalfedgeHandle) override {}
    void set_normal(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_normal(OM::VertexHandle, const OM::Vec3d&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4f&) override {}
    void set_status(OM::VertexHandle, const OM::Attributes::StatusInfo&) override {}
    void set_next(OM::HalfedgeHandle, OM::HalfedgeHandle) override {}
    void set_face(OM::HalfedgeHandle, OM::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec2f&) override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec3f&) override {}
    void set_status(OM::HalfedgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3f&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4f&) override {}
    void set_status(OM::EdgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3d&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4f&) override {}
    void set_status(OM::FaceHandle, const OM::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}

private:
    bool valid(OM::VertexHandle v) const {
        return v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < out_.positions.size();
    }

    // The OBJ reader sets a texture coordinate per face corner on the corner's vertex, before it
    // adds the face: the vertex may be out of range (the face then fails) or already have one.
    void record_texcoord(OM::VertexHandle v, float s, float t) {
        if (out_.texcoords.empty() || !valid(v)) return;
        const auto i = static_cast<std::size_t>(v.idx());
        const glm::vec2 value(s, t);
        if (out_.texcoord_set[i] == 1 && out_.texcoords[i] != value) {
            ++out_.texcoord_conflicts;
            out_.texcoord_set[i] = 2;  // counted once however many it gets
        }
        out_.texcoords[i] = value;
        if (out_.texcoord_set[i] == 0) out_.texcoord_set[i] = 1;
    }

    RawMesh& out_;
    const ScanResult& scan_;
};

// Discards what is written to it.
class NullBuffer final : public std::streambuf {
protected:
    int overflow(int c) override { return traits_type::not_eof(c); }
    std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

// OpenMesh reports through omerr/omlog/omout and, in places, straight to std::cerr; gimg prints
// one clean line instead. Also holds the lock that serialises reads (the reader singletons keep
// per-read state).
class QuietOpenMesh {
public:
    QuietOpenMesh() : lock_(mutex()) {
        was_enabled_[0] = ::omerr().is_enabled();
        was_enabled_[1] = ::omlog().is_enabled();
        was_enabled_[2] = ::omout().is_enabled();
        ::omerr().disable();
        ::omlog().disable();
        ::omout().disable();
        cerr_ = std::cerr.rdbuf(&null_);
        clog_ = std::clog.rdbuf(&null_);
    }
    ~QuietOpenMesh() {
        std::cerr.rdbuf(cerr_);
        std::clog.rdbuf(clog_);
        if (was_enabled_[0]) ::omerr().enable();
        if (was_enabled_[1]) ::omlog().enable();
        if (was_enabled_[2]) ::omout().enable();
    }
    QuietOpenMesh(const QuietOpenMesh&) = delete;
    QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> lock_;
    NullBuffer null_;
    std::streambuf* cerr_ = nullptr;
    std::streambuf* clog_ = nullptr;
    bool was_enabled_[3] = {};
};

// A file only this process knows, removed when it goes out of scope.
class TemporaryFile {
public:
    TemporaryFile(const std::string& contents, const std::string& extension) {
        std::error_code ec;
        const std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
        std::string name = ((ec ? std::filesystem::path("/tmp") : dir) / "gimg-read-XXXXXX").string() + extension;
        const int fd = mkstemps(name.data(), static_cast<int>(extension.size()));
        if (fd < 0) {
            throw std::runtime_error("cannot create a temporary file in " + dir.string() + ": " + std::strerror(errno));
        }
        path_ = name;
        std::size_t written = 0;
        while (written < contents.size()) {
            const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                const int err = errno;
                ::close(fd);
                std::filesystem::remove(path_, ec);
                throw std::runtime_error("cannot write a temporary file in " + dir.string() + ": " +
                                         std::strerror(err));
            }
            written += static_cast<std::size_t>(n);
        }
        ::close(fd);
    }
    ~TemporaryFile() {
        std::error_code ec;
        std::filesystem::remove(path_, ec);
    }
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

void check_against_scan(const RawMesh& raw, const ScanResult& scan) {
    if (raw.positions.size() != scan.vertices) {
        mismatch(std::to_string(raw.positions.size()) + " vertices read, " + std::to_string(scan.vertices) +
                 " counted");
    }
    if (raw.face_count() != scan.reader_faces) {
        mismatch(std::to_string(raw.face_count()) + " faces read, " + std::to_string(scan.reader_faces) + " counted");
    }
    for (const glm::vec3& p : raw.positions) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) mismatch("a NaN coordinate read");
    }
    Fingerprint vertices, faces;
    for (const glm::vec3& p : raw.positions) vertices.add_position(p.x, p.y, p.z);
    for (std::size_t f = 0; f < raw.face_count(); ++f) {
        faces.add(raw.face_offsets[f + 1] - raw.face_offsets[f]);
        for (std::uint32_t k = raw.face_offsets[f]; k < raw.face_offsets[f + 1]; ++k) faces.add(raw.face_indices[k]);
    }
    if (!(vertices == scan.vertex_fingerprint)) mismatch("the vertex coordinates read differ");
    if (!(faces == scan.face_fingerprint)) mismatch("the faces read differ");
}

}  // namespace

RawMesh read_with_openmesh(const ScanResult& scan) {
    RawMesh raw;
    const TemporaryFile file(scan.reader_bytes, "." + scan.format);
    {
        const QuietOpenMesh quiet;
        RecordingImporter importer(raw, scan);
        OM::IO::Options options;
        if (scan.has_texcoords) options += OM::IO::Options::VertexTexCoord;
        if (!OM::IO::IOManager().read(file.path(), importer, options)) mismatch("the reader failed");
    }
    check_against_scan(raw, scan);
    return raw;
}

}  // namespace gimg::geo::io
