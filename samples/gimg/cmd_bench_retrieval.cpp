// gimg bench retrieval [--models N] [--json FILE]
//
// Retrieval speed on a synthetic database: N turned and perturbed copies of a 10,000-face torus
// (lumps of random height), indexed on the GPU in batches (models per second, no file loading),
// then the time of one query (its image and reduction, and the matching) against databases of
// 100, 1,000 and N models.
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/shapes.h"
#include "gimg/passes/retrieval.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace gimg::cli {

namespace {

struct RetrievalBenchOptions {
    std::uint32_t models = 10000;
    std::string json, descriptor = "image";
};

geo::Mesh perturbed_copy(const geo::Mesh& base, std::mt19937_64& rng) {
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    geo::Mesh m = base;
    const double a = 0.05 * uniform(rng), f = 2.0 + 4.0 * uniform(rng);
    const glm::dvec4 q = glm::normalize(glm::dvec4(gauss(rng), gauss(rng), gauss(rng), gauss(rng)));
    const glm::dmat3 turn = glm::mat3_cast(glm::dquat(q.w, q.x, q.y, q.z));
    for (auto& p : m.positions) p = turn * (p * (1.0 + a * std::sin(f * p.x) * std::cos(f * p.z)));
    m.normals.clear();
    return m;
}

void run_retrieval_bench(const RetrievalBenchOptions& o, const GlobalOptions& global) {
    auto ctx = open_context(global);
    const geo::Mesh base = geo::make_torus(0.35, 0.15, 100, 50);  // 10,000 faces
    std::mt19937_64 rng(23);
    passes::RetrievalOptions options;
    const bool panorama = o.descriptor == "panorama";
    if (panorama) options.descriptor = passes::RetrievalDescriptor::Panorama;
    // Panorama's features (three raw images) are large: each chunk is kept as its descriptors.
    std::vector<std::vector<float>> features;
    double feature_ms = 0.0;
    constexpr std::uint32_t kChunk = 256;  // copies in memory at once
    for (std::uint32_t done = 0; done < o.models;) {
        const std::uint32_t n = std::min(kChunk, o.models - done);
        std::vector<geo::Mesh> copies;
        for (std::uint32_t i = 0; i < n; ++i) copies.push_back(perturbed_copy(base, rng));
        std::vector<std::vector<float>> chunk;
        feature_ms += time_ms([&] {
            chunk = passes::cylinder_features(*ctx, copies, options);
            if (panorama) chunk = passes::describe_features(options, chunk);
        });
        for (auto& f : chunk) features.push_back(std::move(f));
        done += n;
    }
    const geo::Mesh query = perturbed_copy(base, rng);
    nlohmann::json sizes = nlohmann::json::array();
    if (!global.quiet) {
        std::printf("gimg bench retrieval on %s: %u copies of a %zu-face torus\n", ctx->device_info().name.c_str(),
                    o.models, base.face_count());
        std::printf("indexing: %.0f models a second (images and reduction; no file loading)\n",
                    1000.0 * o.models / std::max(feature_ms, 1e-9));
    }
    std::vector<std::uint32_t> database_sizes;
    for (std::uint32_t size : {100u, 1000u, o.models})
        if (size <= o.models && std::find(database_sizes.begin(), database_sizes.end(), size) == database_sizes.end())
            database_sizes.push_back(size);
    for (std::uint32_t size : database_sizes) {
        const std::vector<std::vector<float>> subset(features.begin(), features.begin() + size);
        const passes::ShapeDatabase db =
            panorama ? passes::panorama_database(subset, std::vector<std::string>(size), std::vector<std::string>(size))
                     : passes::build_shape_database(subset, std::vector<std::string>(size),
                                                    std::vector<std::string>(size), options);
        std::vector<double> project, match;
        for (int run = 0; run < 5; ++run) {
            std::vector<float> f;
            project.push_back(time_ms([&] { f = passes::cylinder_features(*ctx, {query}, options).front(); }));
            match.push_back(time_ms([&] { (void)passes::search_shapes(db, f, passes::PoseHandling::BestOfFour); }));
        }
        std::sort(project.begin(), project.end());
        std::sort(match.begin(), match.end());
        if (!global.quiet)
            std::printf(
                "database of %5u (k = %u): query image and reduction %.2f ms, matching %.3f ms (medians of 5)\n", size,
                db.k, project[2], match[2]);
        sizes.push_back({{"models", size}, {"k", db.k}, {"projection_ms", project[2]}, {"matching_ms", match[2]}});
    }
    nlohmann::json j{{"models", o.models},
                     {"descriptor", o.descriptor},
                     {"faces", base.face_count()},
                     {"index_models_per_second", 1000.0 * o.models / std::max(feature_ms, 1e-9)},
                     {"databases", sizes}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

}  // namespace

void add_bench_retrieval_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<RetrievalBenchOptions>();
    auto* cmd = bench.add_subcommand("retrieval", "Retrieval speed on a synthetic database of perturbed copies");
    add_count_option(cmd, "--models", o->models, 100, 1000000, "Copies in the database (default 10000)");
    cmd->add_option("--descriptor", o->descriptor, "image (default) or panorama (as gimg index)")
        ->check(CLI::IsMember({"image", "panorama"}));
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_retrieval_bench(*o, global); }); });
}

}  // namespace gimg::cli
