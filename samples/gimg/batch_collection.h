#pragma once
// The models of a `gimg batch` collection and their shards.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gimg::cli {

struct Model {
    std::filesystem::path path;  // to open
    std::string relative;        // as the collection names it: the path below the folder, or the list's line
    std::string name;            // its output folder: the file's stem, made unique with a hash of `relative`
};

// A file the loaders read by its extension: .obj, .off, .ply or .stl (any case).
bool is_mesh_file(const std::filesystem::path& path);

// A folder searched recursively for .obj, .off, .ply and .stl files, or a text file listing one
// path a line (relative to the list's folder; blank lines and lines starting with # skipped).
// Sorted by `relative`, each once. Throws geo::InputError when there is nothing to run.
std::vector<Model> collect_models(const std::filesystem::path& inputs);

struct Shard {
    std::uint32_t index = 0, count = 1;
};
// "K/N" with 0 <= K < N (empty: the whole collection).
Shard parse_shard(const std::string& text);
// The shard a model belongs to: FNV-1a of `relative` modulo N, the same on every machine.
std::uint32_t shard_of(const Model& model, std::uint32_t count);

// The lines of one results file that parse, by model (a later line replaces an earlier one).
std::map<std::string, nlohmann::json> read_results(const std::filesystem::path& file);

// Every results.jsonl and results-K-of-N.jsonl in the folders, by model. Throws geo::InputError for
// no folder or results, a shard K of N missing, or a model in two files (shards of different runs).
std::map<std::string, nlohmann::json> read_batch_results(const std::vector<std::string>& folders);

}  // namespace gimg::cli
