// gimg batch COMMAND --inputs DIR|LIST --out DIR [--shard K/N] [--resume] [-- COMMAND'S OPTIONS]
// gimg batch merge DIR... [--out FILE]
// A per-model command over a collection with one device: each model's files in DIR/<model>/, one
// line per model in DIR/results.jsonl (results-K-of-N.jsonl for a shard), failures recorded and
// passed over, finished models skipped by --resume. docs/cluster.md runs it on Slurm.
#include "batch_collection.h"
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "progress_line.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"

#include <fcntl.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

namespace gimg::cli {

namespace {

struct BatchOptions {
    std::string command, inputs, out, shard;
    std::vector<std::string> rest;  // after the command: merge's folders, or the command's options
    bool resume = false;
};

// The per-model commands: they read one mesh and write a folder, or one file into the model's
// folder (repair), or only JSON (info, features).
const std::set<std::string> kFolderCommands{"cylinder", "sphere", "gim", "maps", "quadmap", "deform", "roundtrip"};
const std::map<std::string, std::string> kFileCommands{{"repair", "repaired.ply"}};
// The commands that need no Vulkan device.
const std::set<std::string> kHostCommands{"info", "repair"};

// One JSON line appended with a single write and synced, so a killed run leaves whole lines (a
// torn last line at worst, which the next --resume drops).
void append_line(const std::filesystem::path& file, const nlohmann::json& line) {
    const std::string text = line.dump() + "\n";
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw geo::EnvironmentError(file.string() + ": cannot open for appending");
    const ssize_t n = ::write(fd, text.data(), text.size());
    const int synced = ::fsync(fd);
    ::close(fd);
    if (n != ssize_t(text.size()) || synced != 0) throw geo::EnvironmentError(file.string() + ": cannot append");
}

nlohmann::json read_json_file(const std::filesystem::path& file) {
    std::ifstream in(file);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    return j.is_discarded() ? nlohmann::json(nullptr) : j;
}

// Runs `gimg COMMAND INPUT --out DIR --json DIR/result.json OPTIONS` in this process; the message
// of what stopped it, or empty. Options the command does not take stop the whole batch.
std::string run_one(const BatchOptions& o, const Model& model, const std::filesystem::path& dir,
                    const std::shared_ptr<Context>& context) {
    CLI::App app;
    app.require_subcommand(1);
    app.fallthrough();
    GlobalOptions inner;
    inner.quiet = true;
    inner.context = context;
    add_commands(app, inner);
    std::vector<std::string> args{o.command, model.path.string()};
    if (kFolderCommands.count(o.command)) args.insert(args.end(), {"--out", dir.string()});
    if (auto file = kFileCommands.find(o.command); file != kFileCommands.end())
        args.insert(args.end(), {"--out", (dir / file->second).string()});
    args.insert(args.end(), {"--json", (dir / "result.json").string()});
    args.insert(args.end(), o.rest.begin(), o.rest.end());
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw geo::InputError("batch: " + o.command + " does not take these options: " +
                              std::string(e.what()).substr(0, std::string(e.what()).find('\n')));
    } catch (const geo::InputError& e) {
        return e.what();
    } catch (const Error& e) {
        return e.what();
    } catch (const std::bad_alloc&) {
        return "out of memory";
    } catch (const std::exception& e) {
        return e.what();
    }
    return {};
}

void run_batch(const BatchOptions& o, const GlobalOptions& global) {
    if (o.inputs.empty() || o.out.empty()) throw geo::InputError("batch needs --inputs and --out");
    if (o.command == "batch") throw geo::InputError("batch cannot run batch");
    if (!kFolderCommands.count(o.command) && !kFileCommands.count(o.command) && o.command != "info" &&
        o.command != "features")
        throw geo::InputError(
            "batch runs the per-model commands: info, repair, features, cylinder, sphere, gim, maps, "
            "quadmap, deform, roundtrip; not '" +
            o.command + "'");
    const Shard shard = parse_shard(o.shard);
    const std::vector<Model> all = collect_models(o.inputs);
    std::vector<Model> mine;
    for (const Model& m : all)
        if (shard_of(m, shard.count) == shard.index) mine.push_back(m);
    const std::filesystem::path out(o.out);
    make_output_folder("--out", out);
    const std::filesystem::path results = out / (shard.count == 1 ? std::string("results.jsonl")
                                                                  : "results-" + std::to_string(shard.index) + "-of-" +
                                                                        std::to_string(shard.count) + ".jsonl");
    std::set<std::string> done;
    if (!std::filesystem::exists(results)) {
        geo::write_file_atomically(results, "");  // a shard with no model still reports, for merge
    } else {
        if (!o.resume)
            throw geo::InputError(results.string() +
                                  " holds an earlier run: add --resume to finish it, or choose another --out");
        // Keep the finished models' lines (a torn or failed one goes); a model whose files are all
        // there but whose line was not written yet gets its line now.
        std::map<std::string, nlohmann::json> kept = read_results(results);
        std::string text;
        for (const Model& m : mine) {
            const std::filesystem::path json = out / m.name / "result.json";
            if (!std::filesystem::exists(json)) continue;
            auto it = kept.find(m.name);
            nlohmann::json line = it != kept.end() && it->second.value("status", "") == "ok"
                                      ? it->second
                                      : nlohmann::json{{"model", m.name},  {"input", m.relative},
                                                       {"status", "ok"},   {"result", read_json_file(json)},
                                                       {"error", nullptr}, {"seconds", nullptr}};
            text += line.dump() + "\n";
            done.insert(m.name);
        }
        geo::write_file_atomically(results, text);
    }

    std::shared_ptr<Context> context;
    if (!kHostCommands.count(o.command)) context = open_context(global);
    ProgressLine progress(global.quiet);
    const auto start = std::chrono::steady_clock::now();
    std::size_t ran = 0, failed = 0;
    const std::size_t pending = mine.size() - done.size();
    for (const Model& m : mine) {
        if (done.count(m.name)) continue;
        const std::filesystem::path dir = out / m.name;
        if (!kFolderCommands.count(o.command)) std::filesystem::create_directories(dir);
        const auto t0 = std::chrono::steady_clock::now();
        const std::string error = run_one(o, m, dir, context);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!error.empty()) {
            ++failed;
            std::error_code ec;
            std::filesystem::remove(dir, ec);  // only when empty: a failed model leaves nothing
        }
        append_line(results, {{"model", m.name},
                              {"input", m.relative},
                              {"status", error.empty() ? "ok" : "failed"},
                              {"result", error.empty() ? read_json_file(dir / "result.json") : nlohmann::json(nullptr)},
                              {"error", error.empty() ? nlohmann::json(nullptr) : nlohmann::json(error)},
                              {"seconds", seconds}});
        ++ran;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double rate = elapsed > 0.0 ? double(ran) / elapsed : 0.0;
        progress.show("batch %s: %zu/%zu models (%zu failed), %.1f models/s, %.0f s left", o.command.c_str(), ran,
                      pending, failed, rate, rate > 0.0 ? double(pending - ran) / rate : 0.0);
    }
    progress.finish();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!global.quiet)
        std::printf(
            "batch %s: %zu models in this shard of %zu: %zu ran (%zu failed), %zu done before; %.1f s, %.2f "
            "models/s; %s\n",
            o.command.c_str(), mine.size(), all.size(), ran, failed, done.size(), elapsed,
            elapsed > 0.0 ? double(ran) / elapsed : 0.0, results.string().c_str());
}

// Every results file in the folders, joined: each model once (its last line in its shard's file).
void run_merge(const BatchOptions& o, const GlobalOptions& global) {
    const std::map<std::string, nlohmann::json> merged = read_batch_results(o.rest);
    const std::filesystem::path target =
        o.out.empty() ? std::filesystem::path(o.rest.front()) / "results.jsonl" : std::filesystem::path(o.out);
    std::string text;
    std::size_t failed = 0;
    for (const auto& [model, line] : merged) {
        text += line.dump() + "\n";
        failed += line.value("status", "") != "ok";
    }
    geo::write_file_atomically(target, text);
    if (!global.quiet)
        std::printf("merged %zu models (%zu failed) into %s\n", merged.size(), failed, target.string().c_str());
}

}  // namespace

void add_batch_commands(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<BatchOptions>();
    auto* cmd = app.add_subcommand("batch", "A per-model command over a collection (sharded, resumable), or merge");
    cmd->add_option("command", o->command, "The command to run per model, or merge")->required();
    cmd->add_option("rest", o->rest, "merge: the runs' folders; else after --: the command's own options");
    cmd->add_option("--inputs", o->inputs, "A folder of meshes (searched recursively), or a file listing them");
    cmd->add_option("--out", o->out, "Output folder (each model in <model>/, results.jsonl); merge: the joined file");
    cmd->add_option("--shard", o->shard, "K/N: this process's share of the collection (0 <= K < N)");
    cmd->add_flag("--resume", o->resume, "Finish an earlier run: skip the models whose files are complete");
    cmd->callback([o, &global] {
        if (o->command == "merge") return run_merge(*o, global);
        run_batch(*o, global);
    });
}

}  // namespace gimg::cli
