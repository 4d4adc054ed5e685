// ndfmip: filters (mipmaps) normal maps so that shading stays right at every distance.
#include <cstdio>
#include <new>

#include "cli.h"
#include "ndfmip/limits.h"

int main(int argc, char** argv) {
    CLI::App app{"ndfmip " NDFMIP_VERSION ": normal-map filtering (Toksvig; Han et al. 2007)"};
    app.set_version_flag("--version", "ndfmip " NDFMIP_VERSION);
    app.require_subcommand(1);
    // Usage errors are one line, like every other error (CLI11's default adds a second).
    // CLI11 quotes the arguments it rejects whole: keep the line short whatever was typed.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return "ndfmip: error: " + ndfmip::shortened(e.what(), 300) + " (see --help)\n";
    });
    // --max-pixels and --max-memory may come before or after the subcommand.
    app.fallthrough();
    ndfmip::cli::addLimitOptions(app);
    ndfmip::cli::addBakeCommand(app);
    ndfmip::cli::addInspectCommand(app);
    ndfmip::cli::addLutCommand(app);
    ndfmip::cli::addDemoCommand(app);
    ndfmip::cli::addCompareCommand(app);
    ndfmip::cli::addRenderCommand(app);
    ndfmip::cli::addViewCommand(app);
    ndfmip::cli::addEvalCommand(app);
    ndfmip::cli::addGltfCommand(app);
    ndfmip::cli::addEnvmapCommand(app);
    ndfmip::cli::requireFiniteNumbers(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const ndfmip::cli::Failure& e) {
        std::fprintf(stderr, "ndfmip: error: %s\n", ndfmip::shortened(e.what(), 1024).c_str());
        return 1;
    } catch (const std::bad_alloc&) { // one line naming the file, as a refused size would
        std::fprintf(stderr, "ndfmip: error: %s\n", ndfmip::outOfMemoryMessage().c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ndfmip: internal error: %s\n",
                     ndfmip::shortened(e.what(), 300).c_str());
        return 2;
    }
    return 0;
}
