// ndfmip lut: Toksvig's 2D lookup table (T eq. 9), optionally with the phase-out of T eq. 11.
#include <cstdio>
#include <memory>

#include "cli.h"
#include "ndfmip/io.h"
#include "ndfmip/toksvig.h"

namespace ndfmip::cli {

void addLutCommand(CLI::App& app) {
    auto options = std::make_shared<ToksvigLutOptions>();
    auto output = std::make_shared<std::string>();
    CLI::App* c = app.add_subcommand(
        "lut", "write Toksvig's lookup table: columns Na.H, rows Na.Na (row 0 = 0, top)");
    c->add_option("--exponent", options->exponent, "Blinn-Phong exponent s")
        ->required()
        ->check(CLI::Range(1e-3f, 1e5f));
    c->add_option("--size", options->size, "N: the table is N x N")
        ->check(CLI::Range(2, 8192))
        ->capture_default_str();
    c->add_option("--bits", options->bitDepth,
                  "phase the filtering out where b-bit normals make |Na| imprecise (0: off)")
        ->check(CLI::Range(0, 16) & !CLI::IsMember({1}))
        ->capture_default_str();
    c->add_option("--threshold", options->threshold, "largest tolerated relative intensity error")
        ->check(CLI::Range(1e-6f, 1e3f))
        ->capture_default_str();
    c->add_option("-o,--output", *output, "output .exr (float) or .png (16-bit)")->required();
    c->callback([options, output] {
        Image lut = toksvigLut(*options);
        bool png = output->size() > 4 && output->substr(output->size() - 4) == ".png";
        Status s = png ? savePng(*output, lut, 16) : saveExr(*output, lut);
        if (!s) throw Failure(s.error);
        std::printf("lut: %dx%d, s = %g%s -> %s\n", lut.width, lut.height, options->exponent,
                    options->bitDepth ? ", phase-out on" : "", output->c_str());
    });
}

} // namespace ndfmip::cli
