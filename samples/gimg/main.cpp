// gimg command line. Exit codes: 0 success, 2 bad input or usage (with a one-line message),
// 1 any other failure (no Vulkan device, device lost, out of memory).
#include "commands.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"

#include "gimg/geometry/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <new>
#include <string>

namespace {

// CLI11's messages in one line: its own text, without the hints on further lines.
std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

int fail(int code, const std::string& message) {
    // What was printed before the error comes first, also when stdout is a buffered pipe.
    std::fflush(stdout);
    std::fprintf(stderr, "gimg: error: %s\n", message.c_str());
    return code;
}

// Standard output that could not be written (a full disk, a closed pipe) is a failure too.
int finish(int code) {
    if (std::fflush(stdout) != 0 || std::ferror(stdout))
        return fail(1, std::string("cannot write to standard output: ") + std::strerror(errno));
    return code;
}

}  // namespace

namespace gimg::cli {

void add_commands(CLI::App& app, GlobalOptions& global) {
    add_demo_command(app, global);
    add_info_command(app, global);
    add_repair_command(app, global);
    add_compare_command(app, global);
    add_render_command(app, global);
    add_cylinder_command(app, global);
    add_reconstruct_command(app, global);
    add_roundtrip_command(app, global);
    add_gim_command(app, global);
    add_quadmap_commands(app, global);
    add_maps_command(app, global);
    add_polycube_command(app, global);
    add_sphere_command(app, global);
    add_sample_command(app, global);
    add_retrieval_commands(app, global);
    add_bench_command(app, global);
    add_devices_command(app, global);
    add_batch_commands(app, global);
}

}  // namespace gimg::cli

int main(int argc, char** argv) {
    using namespace gimg::cli;
    gimg::geo::remove_outputs_on_signals();
#if defined(__GLIBC__)
    // Batches allocate and free arrays of tens of MB (meshes' texels, lavapipe's device memory).
    // glibc maps each afresh and the kernel zeroes every page again: panorama indexing spent about
    // 15 % of its time on those faults. Kept in the heap, the memory is reused.
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
    CLI::App app{
        "gimg: triangle meshes to geometry images and parameterizations, and back, on a "
        "Vulkan render graph"};
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "Print help for every command");
    // Global options also after the command (`gimg sphere m.off --out d --quiet`): the
    // commands, made after this, inherit it and pass options they do not know up here.
    app.fallthrough();
    GlobalOptions global;
    app.add_flag("-v,--verbose", global.verbose, "Print the chosen Vulkan device and progress");
    app.add_flag("-q,--quiet", global.quiet, "Print nothing but errors");
    add_commands(app, global);

    // `--json -` writes the figures to standard output, so nothing else goes there.
    for (int i = 1; i + 1 < argc; ++i)
        if (std::string(argv[i]) == "--json" && std::string(argv[i + 1]) == "-") global.quiet = true;
    if (argc > 1 && argv[1][0] != '-') {
        std::string names;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands({})) {
            known = known || sub->get_name() == argv[1];
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!known) return fail(2, std::string("unknown command '") + argv[1] + "'; the commands are " + names);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return finish(app.exit(e));
    } catch (const CLI::CallForAllHelp& e) {
        return finish(app.exit(e));
    } catch (const CLI::RequiredError& e) {
        if (argc == 1) return fail(2, "no command given; `gimg --help` lists them");
        return fail(2, first_line(e.what()) + " (see --help)");
    } catch (const CLI::ParseError& e) {
        return fail(2, first_line(e.what()) + " (see --help)");
    } catch (const gimg::geo::InputError& e) {
        return fail(2, e.what());
    } catch (const gimg::Error& e) {
        return fail(e.is_input_error() ? 2 : 1, e.what());
    } catch (const std::bad_alloc&) {
        return fail(1, "out of memory: the input needs more memory than this machine has; try a smaller size or model");
    } catch (const std::filesystem::filesystem_error& e) {
        return fail(1, e.path1().string() + ": " + e.code().message());
    } catch (const std::exception& e) {
        return fail(1, e.what());
    }
    return finish(0);
}
