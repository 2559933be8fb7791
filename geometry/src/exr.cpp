#include "gimg/geometry/exr.h"

#include "gimg/geometry/error.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include "gimg/geometry/atomic_file.h"

#include <ImfIO.h>

#include <cstdint>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>

namespace gimg::geo {

namespace {

// The encoded file in memory, so that it goes to disk by the output policy (atomic_file.h).
class MemoryStream : public Imf::OStream {
public:
    explicit MemoryStream(const std::string& name) : Imf::OStream(name.c_str()) {}
    void write(const char c[], int n) override {
        if (at_ + std::size_t(n) > bytes.size()) bytes.resize(at_ + std::size_t(n));
        std::memcpy(bytes.data() + at_, c, std::size_t(n));
        at_ += std::size_t(n);
    }
    std::uint64_t tellp() override { return at_; }
    void seekp(std::uint64_t pos) override { at_ = std::size_t(pos); }
    std::string bytes;

private:
    std::size_t at_ = 0;
};

}  // namespace

void write_exr(const FloatImage& image, const std::filesystem::path& path) {
    if (image.width == 0 || image.height == 0 || image.channels.empty())
        throw InputError("cannot write " + path.string() + ": empty image");
    const std::size_t pixels = std::size_t(image.width) * image.height;
    for (const auto& [name, data] : image.channels)
        if (data.size() != pixels)
            throw InputError("cannot write " + path.string() + ": channel " + name + " has the wrong size");
    MemoryStream encoded(path.string());
    try {
        Imf::Header header(int(image.width), int(image.height));
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (const auto& [name, data] : image.channels) {
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
            frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(data.data())),
                                          sizeof(float), sizeof(float) * image.width));
        }
        Imf::OutputFile file(encoded, header);
        file.setFrameBuffer(frame);
        file.writePixels(int(image.height));
    } catch (const std::exception& e) {
        throw InputError("cannot write " + path.string() + ": " + e.what());
    }
    write_file_atomically(path, encoded.bytes);
}

namespace {
constexpr int kMaxSide = 65536;  // the widest and tallest image read
}  // namespace

FloatImage read_exr(const std::filesystem::path& path) {
    if (std::filesystem::is_directory(path))
        throw InputError("cannot read " + path.string() + ": is a folder, not an image");
    if (!std::filesystem::is_regular_file(path)) throw InputError("cannot read " + path.string() + ": no such file");
    try {
        // OpenEXR sizes its line buffers from the header as the file opens: a 392-byte file claiming
        // 16.7 million columns asks for 2.2 GB. Its own check refuses wider first (one limit for the
        // whole process, which gimg's writes stay under).
        static std::once_flag limit;
        std::call_once(limit, [] { Imf::Header::setMaxImageSize(kMaxSide, kMaxSide); });
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        const Imath::Box2i display = file.header().displayWindow();
        if (window.min != display.min || window.max != display.max)
            throw InputError("cannot read " + path.string() +
                             ": its data window does not cover its display window (gimg reads whole images)");
        FloatImage image;
        const long w = long(window.max.x) - window.min.x + 1, h = long(window.max.y) - window.min.y + 1;
        if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide)
            throw InputError("cannot read " + path.string() + ": implausible size");
        // Nor more pixels than its bytes can hold: deflate packs at most about 1,000 to 1.
        std::size_t channels = 0;
        for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) ++channels;
        const double claimed = double(w) * double(h) * double(channels) * sizeof(float);
        const double bytes = double(std::filesystem::file_size(path));
        if (claimed > std::max(64.0 * 1024 * 1024, 2048.0 * bytes))
            throw InputError("cannot read " + path.string() + ": its header claims " + std::to_string(w) + " x " +
                             std::to_string(h) + " pixels of " + std::to_string(channels) +
                             (channels == 1 ? " channel" : " channels") + ", more than its " +
                             std::to_string(std::size_t(bytes)) + " bytes can hold");
        image.width = std::uint32_t(w);
        image.height = std::uint32_t(h);
        Imf::FrameBuffer frame;
        for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
            auto& data = image.channels[it.name()];
            data.assign(std::size_t(w) * h, 0.0f);
            // Slices are addressed from the data window's origin.
            char* base =
                reinterpret_cast<char*>(data.data()) -
                (std::ptrdiff_t(window.min.x) + std::ptrdiff_t(window.min.y) * w) * std::ptrdiff_t(sizeof(float));
            frame.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * std::size_t(w)));
        }
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError("cannot read " + path.string() + ": " + e.what());
    }
}

}  // namespace gimg::geo
