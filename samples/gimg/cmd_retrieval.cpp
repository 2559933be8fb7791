// gimg index DIR_OR_LIST --out DB.json [--size 144] [--reduced 48] [--variance 0.95] [--json FILE]
// gimg search DB.json MESH [--k N] [--pose aligned|best-of-four] [--json FILE]
// gimg eval DB.json [--pose aligned|best-of-four] [--json FILE]
// Retrieval from cylindrical images (the thesis's chapter 5; docs/retrieval.md).
#include "batch_collection.h"
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "progress_line.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/image.h"
#include "gimg/passes/render.h"
#include "gimg/passes/retrieval.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <random>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace gimg::cli {

namespace {

namespace fs = std::filesystem;

struct Model {
    std::string path, label;
};

// A folder (every mesh below it; labels from its classes.tsv, else the parent folder's name) or a
// list file (a path a line, a tab and a label optional).
std::vector<Model> models_of(const std::string& source) {
    std::vector<Model> models;
    const fs::path root = source;
    if (fs::is_directory(root)) {
        std::map<std::string, std::string> labels;
        if (std::ifstream tsv(root / "classes.tsv"); tsv) {
            std::string line;
            std::getline(tsv, line);  // header: class, file, ...
            while (std::getline(tsv, line)) {
                std::istringstream fields(line);
                std::string label, file;
                if (std::getline(fields, label, '\t') && std::getline(fields, file, '\t'))
                    labels[(root / file).lexically_normal().string()] = label;
            }
        }
        for (const auto& e : fs::recursive_directory_iterator(root)) {
            if (!e.is_regular_file() || !is_mesh_file(e.path())) continue;
            const std::string path = e.path().lexically_normal().string();
            const auto known = labels.find(path);
            models.push_back(
                {path, known != labels.end() ? known->second : e.path().parent_path().filename().string()});
        }
        std::sort(models.begin(), models.end(), [](const Model& a, const Model& b) { return a.path < b.path; });
    } else {
        std::ifstream list(root);
        if (!list) throw geo::InputError(source + ": no such folder or list file");
        std::string line;
        while (std::getline(list, line)) {
            if (line.empty()) continue;
            const auto tab = line.find('\t');
            models.push_back({line.substr(0, tab), tab == std::string::npos ? std::string() : line.substr(tab + 1)});
        }
    }
    if (models.empty()) throw geo::InputError(source + ": no meshes (.obj, .off, .ply, .stl) found");
    return models;
}

passes::PoseHandling pose_of(const std::string& text) {
    return text == "aligned" ? passes::PoseHandling::AsAligned : passes::PoseHandling::BestOfFour;
}

struct IndexOptions {
    std::string source, out, json, descriptor = "image";
    std::vector<std::string> shards;  // --from-shards: folders of `gimg batch features` runs
    passes::RetrievalOptions retrieval;
};

// The feature options as given (descriptor by name), checked.
void resolve_feature_options(IndexOptions& o) {
    o.retrieval.descriptor = o.descriptor == "spectrum"           ? passes::RetrievalDescriptor::ThetaSpectrum
                             : o.descriptor == "spectrum2d"       ? passes::RetrievalDescriptor::Spectrum2D
                             : o.descriptor == "spectrum2d-slope" ? passes::RetrievalDescriptor::Spectrum2DSlope
                             : o.descriptor == "panorama"         ? passes::RetrievalDescriptor::Panorama
                                                                  : passes::RetrievalDescriptor::Image;
    if (o.retrieval.cylinders == 2) throw geo::InputError("--cylinders takes 1 or 3");
    if (o.retrieval.reduced % 2 != 0 || o.retrieval.size % o.retrieval.reduced != 0)
        throw geo::InputError("--size must be a multiple of --reduced, and --reduced even");
}

// One model's retrieval feature (before the PCA), as `gimg batch features` computes it per shard.
void run_features(IndexOptions o, const GlobalOptions& global) {
    resolve_feature_options(o);
    const geo::Mesh mesh = geo::load_mesh(o.source);
    auto ctx = open_context(global);
    const std::vector<float> feature = passes::cylinder_features(*ctx, {mesh}, o.retrieval).front();
    if (!global.quiet) std::printf("%s: a feature of %zu values\n", o.source.c_str(), feature.size());
    write_json(o.json, {{"mesh", fs::path(o.source).lexically_normal().string()},
                        {"label", fs::path(o.source).parent_path().filename().string()},
                        {"size", o.retrieval.size},
                        {"reduced", o.retrieval.reduced},
                        {"descriptor", o.descriptor},
                        {"cylinders", o.retrieval.cylinders},
                        {"feature", feature}});
}

// What the database keeps, and the name of the step that made it: PCA's k and kept variance, or
// panorama's descriptors (no PCA).
std::string database_summary(const passes::ShapeDatabase& db) {
    char text[128];
    if (db.options.descriptor == passes::RetrievalDescriptor::Panorama)
        std::snprintf(text, sizeof text, "descriptors of %u values (no PCA)", db.k);
    else
        std::snprintf(text, sizeof text, "k = %u components holding %.1f %% of the variance", db.k,
                      100.0 * db.variance_kept);
    return text;
}
const char* database_step(const passes::ShapeDatabase& db) {
    return db.options.descriptor == passes::RetrievalDescriptor::Panorama ? "descriptors" : "PCA";
}

// One PCA over the features `gimg batch features` wrote per shard: the same database as `gimg
// index` of the whole collection, the models in the same (path) order.
void run_index_from_shards(IndexOptions o, const GlobalOptions& global) {
    std::vector<nlohmann::json> results;
    for (auto& [model, line] : read_batch_results(o.shards))
        if (line.value("status", "") == "ok" && line["result"].is_object() && line["result"].contains("feature"))
            results.push_back(line["result"]);
    if (results.empty())
        throw geo::InputError("--from-shards: no model's features in those folders (gimg batch features)");
    std::sort(results.begin(), results.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
        return a["mesh"].get<std::string>() < b["mesh"].get<std::string>();
    });
    const nlohmann::json& first = results.front();
    o.retrieval.size = first["size"].get<std::uint32_t>();
    o.retrieval.reduced = first["reduced"].get<std::uint32_t>();
    o.retrieval.cylinders = first["cylinders"].get<std::uint32_t>();
    o.descriptor = first["descriptor"].get<std::string>();
    resolve_feature_options(o);
    std::map<std::string, std::string> labels;  // from classes.tsv beside the models, when there is one
    std::vector<std::vector<float>> features;
    std::vector<std::string> paths, names;
    for (const nlohmann::json& r : results) {
        for (const char* key : {"size", "reduced", "cylinders", "descriptor"})
            if (r[key] != first[key])
                throw geo::InputError("--from-shards: " + r["mesh"].get<std::string>() + " has another --" + key +
                                      " than " + first["mesh"].get<std::string>());
        features.push_back(r["feature"].get<std::vector<float>>());
        paths.push_back(r["mesh"].get<std::string>());
        names.push_back(r["label"].get<std::string>());
    }
    if (!o.source.empty())
        for (const Model& m : models_of(o.source)) labels[m.path] = m.label;
    for (std::size_t i = 0; i < paths.size(); ++i)
        if (auto it = labels.find(paths[i]); it != labels.end()) names[i] = it->second;
    passes::ShapeDatabase db;
    const double pca_ms = time_ms([&] { db = passes::build_shape_database(features, paths, names, o.retrieval); });
    passes::write_shape_database(o.out, db);
    if (!global.quiet)
        std::printf("%s: %zu models from the shards, %s (%s %.0f ms)\n", o.out.c_str(), db.size(),
                    database_summary(db).c_str(), database_step(db), pca_ms);
    write_json(o.json, {{"models", db.size()}, {"k", db.k}, {"variance_kept", db.variance_kept}, {"pca_ms", pca_ms}});
}

void run_index(IndexOptions o, const GlobalOptions& global) {
    if (!o.shards.empty()) return run_index_from_shards(std::move(o), global);
    if (o.source.empty()) throw geo::InputError("index takes a folder or list of models, or --from-shards");
    resolve_feature_options(o);
    const std::vector<Model> models = models_of(o.source);
    auto ctx = open_context(global);
    std::vector<geo::Mesh> meshes;
    std::vector<std::string> paths, labels;
    nlohmann::json failed = nlohmann::json::array();
    ProgressLine line(global.quiet);
    double load_ms = 0.0;
    for (std::size_t i = 0; i < models.size(); ++i) {
        line.show("loading %zu of %zu", i + 1, models.size());
        try {
            load_ms += time_ms([&] { meshes.push_back(geo::load_mesh(models[i].path)); });
            paths.push_back(models[i].path);
            labels.push_back(models[i].label);
        } catch (const geo::InputError& e) {
            failed.push_back({{"path", models[i].path}, {"error", e.what()}});  // skipped, never fatal
        }
    }
    line.finish();
    std::vector<std::vector<float>> features;
    const double feature_ms = time_ms([&] { features = passes::cylinder_features(*ctx, meshes, o.retrieval); });
    passes::ShapeDatabase db;
    const double pca_ms = time_ms([&] { db = passes::build_shape_database(features, paths, labels, o.retrieval); });
    passes::write_shape_database(o.out, db);
    if (!global.quiet) {
        std::printf("%s: %zu models indexed (%zu skipped), %s\n", o.out.c_str(), db.size(), failed.size(),
                    database_summary(db).c_str());
        std::printf("load %.0f ms, images and reduction %.0f ms (%.0f models/s), %s %.0f ms\n", load_ms, feature_ms,
                    1000.0 * double(db.size()) / std::max(feature_ms, 1e-9), database_step(db), pca_ms);
        for (const auto& f : failed)
            std::printf("skipped %s: %s\n", f["path"].get<std::string>().c_str(),
                        f["error"].get<std::string>().c_str());
    }
    nlohmann::json j{
        {"models", db.size()}, {"skipped", failed},        {"k", db.k},       {"variance_kept", db.variance_kept},
        {"load_ms", load_ms},  {"feature_ms", feature_ms}, {"pca_ms", pca_ms}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

struct SearchOptions {
    std::string db, mesh, pose = "best-of-four", json, picture;
    std::uint32_t k = 10;
};

void run_search(const SearchOptions& o, const GlobalOptions& global) {
    const passes::ShapeDatabase db = passes::read_shape_database(o.db);
    auto ctx = open_context(global);
    geo::Mesh mesh;
    const double load_ms = time_ms([&] { mesh = geo::load_mesh(o.mesh); });
    std::vector<float> feature;
    const double project_ms = time_ms([&] { feature = passes::cylinder_features(*ctx, {mesh}, db.options).front(); });
    std::vector<passes::ShapeMatch> matches;
    const double match_ms = time_ms([&] { matches = passes::search_shapes(db, feature, pose_of(o.pose)); });
    matches.resize(std::min<std::size_t>(matches.size(), o.k));
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t r = 0; r < matches.size(); ++r) {
        const auto& m = matches[r];
        if (!global.quiet)
            std::printf("%2zu  %-12s %.6g  %s\n", r + 1, db.labels[m.model].c_str(), m.distance,
                        db.paths[m.model].c_str());
        list.push_back(
            {{"rank", r + 1}, {"path", db.paths[m.model]}, {"label", db.labels[m.model]}, {"distance", m.distance}});
    }
    if (!global.quiet)
        std::printf("load %.1f ms, projection %.1f ms, matching %.2f ms\n", load_ms, project_ms, match_ms);
    if (!o.picture.empty()) {
        // The query and its first results (at most 5) side by side, each 240 x 240, same view.
        const std::size_t shown = std::min<std::size_t>(matches.size(), 5);
        passes::RenderOptions view;
        view.width = view.height = 240;
        geo::RgbaImage strip(std::uint32_t(240 * (shown + 1)), 240);
        for (std::size_t i = 0; i <= shown; ++i) {
            const geo::Mesh m = i == 0 ? mesh : geo::load_mesh(db.paths[matches[i - 1].model]);
            const geo::RgbaImage one = passes::render_mesh(*ctx, m, view);
            for (std::uint32_t y = 0; y < 240; ++y)
                for (std::uint32_t x = 0; x < 240; ++x) {
                    std::copy_n(one.at(x, y), 4, strip.at(std::uint32_t(240 * i) + x, y));
                    strip.at(std::uint32_t(240 * i) + x, y)[3] = 255;
                }
        }
        geo::write_png(strip, o.picture);
    }
    nlohmann::json j{{"query", o.mesh},
                     {"results", list},
                     {"pose", o.pose},
                     {"load_ms", load_ms},
                     {"projection_ms", project_ms},
                     {"matching_ms", match_ms}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

// Whether `mesh` (model `q` of the database), turned at random, scaled by 0.1 to 10 and moved,
// finds model q first (or tied with the first).
bool finds_itself(Context& ctx, const passes::ShapeDatabase& db, geo::Mesh mesh, std::size_t q,
                  passes::PoseHandling pose, std::mt19937_64& rng) {
    std::normal_distribution<double> gauss(0.0, 1.0);
    const glm::dvec4 quat = glm::normalize(glm::dvec4(gauss(rng), gauss(rng), gauss(rng), gauss(rng)));
    const glm::dmat3 turn = glm::mat3_cast(glm::dquat(quat.w, quat.x, quat.y, quat.z));
    const double scale = std::exp(std::uniform_real_distribution<double>(std::log(0.1), std::log(10.0))(rng));
    const glm::dvec3 move(gauss(rng), gauss(rng), gauss(rng));
    for (auto& p : mesh.positions) p = scale * (turn * p) + move;
    const auto posed = passes::search_shapes(db, passes::cylinder_features(ctx, {mesh}, db.options).front(), pose);
    for (const auto& m : posed)
        if (m.model == q) return m.distance <= posed.front().distance;
    return false;
}

struct EvalOptions {
    std::string db, pose = "best-of-four", method = "cylinder", queries, json;
};

// Leave-one-out: every model of the database as a query against the others.
void run_eval(const EvalOptions& o, const GlobalOptions& global) {
    const passes::ShapeDatabase db = passes::read_shape_database(o.db);
    auto ctx = open_context(global);
    std::map<std::string, std::size_t> class_size;
    for (const auto& l : db.labels) ++class_size[l];
    std::map<std::string, passes::RetrievalScores> per_class;
    std::map<std::string, std::size_t> per_class_queries;
    passes::RetrievalScores total;
    std::size_t queries = 0;
    double load_ms = 0.0, project_ms = 0.0, match_ms = 0.0;
    std::mt19937_64 rng(17);
    std::size_t found_itself = 0;
    ProgressLine line(global.quiet);
    // D2: every model's histogram first (the database holds cylindrical coefficients only).
    // D2 and silhouettes: every model's descriptor first (the database holds cylindrical
    // coefficients only).
    std::vector<std::vector<float>> other;
    auto other_descriptor = [&](const geo::Mesh& mesh) {
        return o.method == "d2" ? passes::d2_histogram(mesh) : passes::silhouette_descriptor(*ctx, mesh);
    };
    auto other_distance = [&](const std::vector<float>& a, const std::vector<float>& b) {
        if (o.method == "silhouettes") return passes::silhouette_distance(a, b);
        double l1 = 0.0;
        for (std::size_t k = 0; k < a.size(); ++k) l1 += std::abs(double(a[k]) - double(b[k]));
        return l1;
    };
    if (o.method != "cylinder")
        for (std::size_t m = 0; m < db.size(); ++m) {
            line.show("%s of model %zu of %zu", o.method.c_str(), m + 1, db.size());
            geo::Mesh mesh;
            load_ms += time_ms([&] { mesh = geo::load_mesh(db.paths[m]); });
            project_ms += time_ms([&] { other.push_back(other_descriptor(mesh)); });
        }
    // The queries: every model of the database against the others (leave-one-out), or the models of
    // --queries against the whole database.
    const bool held_apart = !o.queries.empty();
    const std::vector<Model> asked = held_apart ? models_of(o.queries) : std::vector<Model>{};
    const std::size_t total_queries = held_apart ? asked.size() : db.size();
    for (std::size_t qi = 0; qi < total_queries; ++qi) {
        line.show("query %zu of %zu", qi + 1, total_queries);
        const std::size_t q = held_apart ? static_cast<std::size_t>(-1) : qi;  // the model left out
        const std::string query_path = held_apart ? asked[qi].path : db.paths[qi];
        const std::string query_label = held_apart ? asked[qi].label : db.labels[qi];
        const std::size_t relevant = class_size[query_label] - (held_apart ? 0 : 1);
        if (relevant == 0) continue;  // nothing to find
        std::vector<passes::ShapeMatch> matches;
        if (o.method != "cylinder") {
            std::vector<float> query_descriptor;
            project_ms += time_ms(
                [&] { query_descriptor = held_apart ? other_descriptor(geo::load_mesh(query_path)) : other[q]; });
            match_ms += time_ms([&] {
                for (std::size_t m = 0; m < db.size(); ++m)
                    if (m != q) matches.push_back({m, other_distance(query_descriptor, other[m])});
                std::stable_sort(matches.begin(), matches.end(),
                                 [](const auto& a, const auto& b) { return a.distance < b.distance; });
            });
        } else {
            geo::Mesh mesh;
            load_ms += time_ms([&] { mesh = geo::load_mesh(query_path); });
            std::vector<float> feature;
            project_ms += time_ms([&] { feature = passes::cylinder_features(*ctx, {mesh}, db.options).front(); });
            match_ms += time_ms([&] { matches = passes::search_shapes(db, feature, pose_of(o.pose), q); });
            if (!held_apart) found_itself += finds_itself(*ctx, db, std::move(mesh), q, pose_of(o.pose), rng);
        }
        std::vector<std::string> ranked;
        for (const auto& m : matches) ranked.push_back(db.labels[m.model]);
        const passes::RetrievalScores s = passes::score_ranking(ranked, query_label, relevant);
        for (auto* acc : {&total, &per_class[query_label]}) {
            acc->nearest_neighbour += s.nearest_neighbour;
            acc->first_tier += s.first_tier;
            acc->second_tier += s.second_tier;
            acc->dcg += s.dcg;
            acc->average_precision += s.average_precision;
        }
        ++per_class_queries[query_label];
        ++queries;
    }
    line.finish();
    if (queries == 0) throw geo::InputError(o.db + ": no query has a model of its class to find; nothing to evaluate");
    auto row = [](const passes::RetrievalScores& s, double n) {
        return nlohmann::json{{"nn", s.nearest_neighbour / n},
                              {"first_tier", s.first_tier / n},
                              {"second_tier", s.second_tier / n},
                              {"dcg", s.dcg / n},
                              {"map", s.average_precision / n}};
    };
    nlohmann::json classes = nlohmann::json::object();
    for (const auto& [label, s] : per_class) classes[label] = row(s, double(per_class_queries[label]));
    const nlohmann::json overall = row(total, double(queries));
    if (!global.quiet) {
        const std::string how = o.method == "d2"            ? std::string("D2 shape distributions")
                                : o.method == "silhouettes" ? std::string("silhouettes (Zernike, 7 views)")
                                : db.options.descriptor == passes::RetrievalDescriptor::Panorama
                                    ? std::string("panorama (three cylinders, L1; no pose variants needed)")
                                    : "cylindrical images, pose " + o.pose;
        std::printf("%s: %zu queries, %s, %s\n", o.db.c_str(), queries,
                    held_apart ? ("held apart in " + o.queries).c_str() : "leave-one-out", how.c_str());
        std::printf("%-14s %6s %6s %6s %6s %6s\n", "class", "NN", "FT", "ST", "DCG", "mAP");
        for (const auto& [label, r] : classes.items())
            std::printf("%-14s %6.3f %6.3f %6.3f %6.3f %6.3f\n", label.c_str(), r["nn"].get<double>(),
                        r["first_tier"].get<double>(), r["second_tier"].get<double>(), r["dcg"].get<double>(),
                        r["map"].get<double>());
        std::printf("%-14s %6.3f %6.3f %6.3f %6.3f %6.3f\n", "overall", overall["nn"].get<double>(),
                    overall["first_tier"].get<double>(), overall["second_tier"].get<double>(),
                    overall["dcg"].get<double>(), overall["map"].get<double>());
        if (o.method == "cylinder" && !held_apart)
            std::printf("a turned, scaled, moved copy finds its original first: %zu of %zu\n", found_itself, queries);
        std::printf("per query: load %.1f ms, projection %.1f ms, matching %.3f ms\n", load_ms / double(queries),
                    project_ms / double(queries), match_ms / double(queries));
    }
    nlohmann::json j{{"queries", queries},
                     {"method", o.method},
                     {"pose", o.pose},
                     {"overall", overall},
                     {"pose_invariance", o.method == "cylinder" && !held_apart
                                             ? nlohmann::json(double(found_itself) / double(queries))
                                             : nlohmann::json(nullptr)},
                     {"held_apart", held_apart},
                     {"classes", classes},
                     {"load_ms_per_query", load_ms / double(queries)},
                     {"projection_ms_per_query", project_ms / double(queries)},
                     {"matching_ms_per_query", match_ms / double(queries)}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

void add_pose_option(CLI::App* cmd, std::string& pose) {
    cmd->add_option("--pose", pose,
                    "best-of-four (default: the query in the four poses PCA's free signs allow, the nearest kept) "
                    "or aligned (as PCA leaves it, the thesis)")
        ->check(CLI::IsMember({"aligned", "best-of-four"}));
}

}  // namespace

void add_retrieval_commands(CLI::App& app, const GlobalOptions& global) {
    auto io = std::make_shared<IndexOptions>();
    auto* index = app.add_subcommand("index", "Index a folder of models for retrieval by cylindrical images");
    index->add_option("source", io->source,
                      "A folder (labels from its classes.tsv or sub-folders) or a list file; with --from-shards, "
                      "optional: the labels");
    index->add_option("--out", io->out, "The database (.json)")->required();
    add_count_option(index, "--size", io->retrieval.size, 8, 4096, "Cylindrical image side (default 144)");
    add_count_option(index, "--reduced", io->retrieval.reduced, 2, 512, "Reduced side (default 48)");
    add_number_option(index, "--variance", io->retrieval.variance, 0.01, 1.0,
                      "Share of the variance the kept components hold (default 0.95)");
    index
        ->add_option(
            "--descriptor", io->descriptor,
            "image (the reduced image, the thesis; default), spectrum (per row, the magnitudes of its "
            "DFT over theta: the same for every turn about the axis), spectrum2d (the magnitudes of "
            "its 2D DFT: also the same turned end over end), spectrum2d-slope (spectrum2d of the image and of its "
            "slope, a second channel) or panorama (PANORAMA's kind: three cylinders of its own, distance and "
            "orientation channels, low-band spectra compared by L1, no PCA)")
        ->check(CLI::IsMember({"image", "spectrum", "spectrum2d", "spectrum2d-slope", "panorama"}));
    add_count_option(index, "--cylinders", io->retrieval.cylinders, 1, 3,
                     "1: the cylinder around the main axis (the thesis; default); 3: one around each principal axis");
    index->add_option("--from-shards", io->shards,
                      "Folders of `gimg batch features` runs: one PCA over their features (docs/cluster.md)");
    index->add_option("--json", io->json, "Write the figures as JSON");
    index->callback([io, &global] {
        run_writing({}, {{"--out", io->out, {".json"}}, json_output(io->json)}, [&] { run_index(*io, global); });
    });

    auto fo = std::make_shared<IndexOptions>();
    auto* features = app.add_subcommand("features", "One model's retrieval feature, as JSON (for gimg batch)");
    features->add_option("mesh", fo->source, "The mesh")->required();
    features->add_option("--json", fo->json, "The feature and its options (.json, or - for standard output)")
        ->required();
    add_count_option(features, "--size", fo->retrieval.size, 8, 4096, "Cylindrical image side (default 144)");
    add_count_option(features, "--reduced", fo->retrieval.reduced, 2, 512, "Reduced side (default 48)");
    features->add_option("--descriptor", fo->descriptor, "As for index")
        ->check(CLI::IsMember({"image", "spectrum", "spectrum2d", "spectrum2d-slope", "panorama"}));
    add_count_option(features, "--cylinders", fo->retrieval.cylinders, 1, 3, "As for index");
    features->callback(
        [fo, &global] { run_writing({fo->source}, {json_output(fo->json)}, [&] { run_features(*fo, global); }); });

    auto so = std::make_shared<SearchOptions>();
    auto* search = app.add_subcommand("search", "The models of a database most like a query mesh");
    search->add_option("db", so->db, "The database (gimg index)")->required();
    search->add_option("mesh", so->mesh, "The query mesh")->required();
    add_count_option(search, "--k", so->k, 1, 1000000, "How many results (default 10)");
    add_pose_option(search, so->pose);
    search->add_option("--picture", so->picture, "Draw the query and its first 5 results side by side (PNG)");
    search->add_option("--json", so->json, "Write the results as JSON");
    search->callback([so, &global] {
        run_writing({so->db, so->mesh}, {json_output(so->json), {"--picture", so->picture, {".png"}}},
                    [&] { run_search(*so, global); });
    });

    auto eo = std::make_shared<EvalOptions>();
    auto* eval = app.add_subcommand("eval", "Leave-one-out retrieval scores of a labelled database");
    eval->add_option("db", eo->db, "The database (gimg index)")->required();
    add_pose_option(eval, eo->pose);
    eval->add_option("--queries", eo->queries,
                     "Held-apart queries against the whole database (a folder with classes.tsv or sub-folders, or a "
                     "list file with labels) instead of leave-one-out");
    eval->add_option("--method", eo->method,
                     "cylinder (the database's cylindrical images, default), silhouettes (7 views, Zernike "
                     "magnitudes: the Light Field Descriptor's idea, the baseline) or d2 (D2 shape distributions: "
                     "the floor), on the same models")
        ->check(CLI::IsMember({"cylinder", "silhouettes", "d2"}));
    eval->add_option("--json", eo->json, "Write the scores as JSON");
    eval->callback([eo, &global] { run_writing({eo->db}, {json_output(eo->json)}, [&] { run_eval(*eo, global); }); });
}

}  // namespace gimg::cli
