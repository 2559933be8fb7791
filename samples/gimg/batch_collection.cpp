// The models of a batch collection, named and sharded (batch_collection.h).
#include "batch_collection.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>

namespace gimg::cli {

namespace {

std::uint64_t fnv1a(const std::string& text) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    return h;
}

bool is_mesh(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl";
}

}  // namespace

std::vector<Model> collect_models(const std::filesystem::path& inputs) {
    std::vector<Model> models;
    if (std::filesystem::is_directory(inputs)) {
        for (const auto& e : std::filesystem::recursive_directory_iterator(inputs))
            if (e.is_regular_file() && is_mesh(e.path()))
                models.push_back({e.path(), std::filesystem::relative(e.path(), inputs).generic_string(), {}});
    } else if (std::filesystem::is_regular_file(inputs)) {
        std::ifstream in(inputs);
        std::string line;
        while (std::getline(in, line)) {
            while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
            if (line.empty() || line[0] == '#') continue;
            const std::filesystem::path p(line);
            models.push_back({p.is_absolute() ? p : inputs.parent_path() / p, line, {}});
        }
    } else {
        throw geo::InputError("--inputs " + inputs.string() + ": no such folder or list");
    }
    if (models.empty()) throw geo::InputError("--inputs " + inputs.string() + ": no meshes (.obj, .off, .ply, .stl)");
    std::sort(models.begin(), models.end(), [](const Model& a, const Model& b) { return a.relative < b.relative; });
    std::map<std::string, int> stems;
    for (const Model& m : models) ++stems[m.path.stem().string()];
    for (Model& m : models) {
        m.name = m.path.stem().string();
        if (stems[m.name] > 1) {
            char suffix[24];
            std::snprintf(suffix, sizeof suffix, "-%08x", unsigned(fnv1a(m.relative) & 0xffffffffu));
            m.name += suffix;
        }
    }
    return models;
}

Shard parse_shard(const std::string& text) {
    if (text.empty()) return {};
    unsigned k = 0, n = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%u/%u%c", &k, &n, &tail) != 2 || n == 0 || k >= n || n > 100000 ||
        text.find_first_not_of("0123456789/") != std::string::npos)
        throw geo::InputError("--shard takes K/N with 0 <= K < N, got '" + text + "'");
    return {k, n};
}

std::uint32_t shard_of(const Model& model, std::uint32_t count) { return std::uint32_t(fnv1a(model.relative) % count); }

}  // namespace gimg::cli
