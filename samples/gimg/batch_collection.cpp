// The models of a batch collection, named and sharded (batch_collection.h).
#include "batch_collection.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

namespace gimg::cli {

namespace {

std::uint64_t fnv1a(const std::string& text) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    return h;
}

}  // namespace

bool is_mesh_file(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl";
}

std::vector<Model> collect_models(const std::filesystem::path& inputs) {
    std::vector<Model> models;
    if (std::filesystem::is_directory(inputs)) {
        for (const auto& e : std::filesystem::recursive_directory_iterator(inputs))
            if (e.is_regular_file() && is_mesh_file(e.path()))
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
    // A list naming a model twice runs it once.
    models.erase(std::unique(models.begin(), models.end(),
                             [](const Model& a, const Model& b) { return a.relative == b.relative; }),
                 models.end());
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

// The lines of a results file that parse, by model (a later line replaces an earlier one).
std::map<std::string, nlohmann::json> read_results(const std::filesystem::path& file) {
    std::map<std::string, nlohmann::json> out;
    std::ifstream in(file);
    std::string text;
    while (std::getline(in, text)) {
        nlohmann::json line = nlohmann::json::parse(text, nullptr, false);
        if (!line.is_object() || !line.contains("model") || !line["model"].is_string()) continue;
        const std::string model = line["model"].get<std::string>();
        out[model] = std::move(line);
    }
    return out;
}

std::map<std::string, nlohmann::json> read_batch_results(const std::vector<std::string>& folders) {
    if (folders.empty()) throw geo::InputError("give the folders of the shards' runs");
    std::map<std::string, nlohmann::json> merged;
    std::map<std::string, std::string> from;
    std::map<int, std::set<int>> shards;  // N -> the K seen
    for (const std::string& folder : folders) {
        if (!std::filesystem::is_directory(folder)) throw geo::InputError(folder + ": not a folder");
        for (const auto& entry : std::filesystem::directory_iterator(folder)) {
            const std::string name = entry.path().filename().string();
            int k = 0, n = 1;
            if (name != "results.jsonl" && std::sscanf(name.c_str(), "results-%d-of-%d.jsonl", &k, &n) != 2) continue;
            shards[n].insert(k);
            for (auto& [model, line] : read_results(entry.path())) {
                if (from.count(model))
                    throw geo::InputError("model " + model + " is in both " + from[model] + " and " +
                                          entry.path().string() + ": shards of different runs?");
                merged[model] = line;
                from[model] = entry.path().string();
            }
        }
    }
    if (merged.empty())
        throw geo::InputError("no results files (results.jsonl, results-K-of-N.jsonl) in those folders");
    for (const auto& [n, ks] : shards)
        for (int k = 0; k < n; ++k)
            if (n > 1 && !ks.count(k))
                throw geo::InputError("shard " + std::to_string(k) + " of " + std::to_string(n) + " is missing");
    return merged;
}

}  // namespace gimg::cli
