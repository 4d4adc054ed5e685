// ndfmip compare A B: error statistics of image A against the reference B, as JSON.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "ndfmip/compare.h"
#include "ndfmip/io.h"

namespace ndfmip::cli {
namespace {

struct CompareArgs {
    std::string a, b, errorImagePath;
    float errorScale = 0.f;
    std::optional<int> channel;
};

Image loadOrFail(const std::string& path) {
    Result<SourceImage> loaded = loadImage(path);
    if (!loaded) throw Failure(loaded.error().message);
    return std::move(loaded->image);
}

// Channel `channel` of `image` alone, or a Failure naming the file when it has no such channel.
Image channelOrFail(const Image& image, int channel, const std::string& path) {
    if (channel < 0 || channel >= image.channels)
        throw Failure(path + ": --channel " + std::to_string(channel) +
                      " is out of range (the image has " + std::to_string(image.channels) +
                      (image.channels == 1 ? " channel)" : " channels)"));
    Image out(image.width, image.height, 1);
    for (size_t t = 0; t < image.texelCount(); ++t)
        out.pixels[t] = image.pixels[t * size_t(image.channels) + size_t(channel)];
    return out;
}

// JSON has no infinity: non-finite numbers are written as null.
nlohmann::ordered_json number(double value) {
    return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

void runCompare(const CompareArgs& args) {
    Image a = loadOrFail(args.a);
    Image b = loadOrFail(args.b);
    if (args.channel) {
        a = channelOrFail(a, *args.channel, args.a);
        b = channelOrFail(b, *args.channel, args.b);
    }
    Result<ImageComparison> compared = compareImages(a, b);
    if (!compared) throw Failure(args.a + " vs " + args.b + ": " + compared.error().message);
    if (!args.errorImagePath.empty()) {
        Status s = savePng(args.errorImagePath, errorImage(a, b, args.errorScale), 8);
        if (!s) throw Failure(s.error);
    }
    const ImageComparison& c = compared.value();
    nlohmann::ordered_json out = {
        {"a", args.a},
        {"b", args.b},
        {"width", c.width},
        {"height", c.height},
        {"channels", c.channels},
        {"rmse", number(c.rmse)},
        {"rel_rmse", number(c.relativeRmse)},
        {"psnr", number(c.psnr)},
        {"energy_ratio", number(c.energyRatio)},
        {"max_abs_error", number(c.maxAbsError)},
    };
    std::printf("%s\n", out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
}

} // namespace

void addCompareCommand(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* c = app.add_subcommand(
        "compare", "compare image A with the reference B; prints error statistics as JSON");
    c->add_option("A", args->a, "image under test (EXR, PNG, ...)")->required();
    c->add_option("B", args->b, "reference image, same size and channels")->required();
    c->add_option("--error-image", args->errorImagePath,
                  "write |A - B| (mean over channels) as a false-colour 8-bit PNG");
    c->add_option("--error-scale", args->errorScale,
                  "error shown as the top colour (0: the 99th percentile)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    c->add_option("--channel", args->channel, "compare only this channel (0 = first)");
    c->callback([args] { runCompare(*args); });
}

} // namespace ndfmip::cli
