// gimg command line. Exit codes: 0 success, 2 bad input or usage (with a one-line message),
// 1 any other failure (no Vulkan device, device lost, out of memory).
#include "commands.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    using namespace gimg::cli;
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
    add_demo_command(app, global);
    add_info_command(app, global);
    add_compare_command(app, global);
    add_render_command(app, global);
    add_cylinder_command(app, global);
    add_reconstruct_command(app, global);
    add_roundtrip_command(app, global);
    add_sphere_command(app, global);
    add_sample_command(app, global);
    add_bench_command(app, global);
    add_devices_command(app, global);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return 2;
    } catch (const gimg::geo::InputError& e) {
        std::fprintf(stderr, "gimg: error: %s\n", e.what());
        return 2;
    } catch (const gimg::Error& e) {
        std::fprintf(stderr, "gimg: error: %s\n", e.what());
        return e.is_input_error() ? 2 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gimg: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
