#include "gimg/geometry/atomic_file.h"

#include "gimg/geometry/error.h"

#include <cstdio>
#include <fstream>
#include <system_error>
#include <unistd.h>

namespace gimg::geo {

void write_file_atomically(const std::filesystem::path& path, std::string_view contents) {
    std::filesystem::path tmp = path;
    tmp += ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError("cannot write " + path.string() + ": folder missing or not writable");
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.flush();
        if (!out) {
            out.close();
            std::filesystem::remove(tmp);
            throw InputError("cannot write " + path.string() + ": write failed (disk full?)");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp);
        throw InputError("cannot write " + path.string() + ": " + ec.message());
    }
}

}  // namespace gimg::geo
