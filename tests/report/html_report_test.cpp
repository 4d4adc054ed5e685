// The report page and the pieces it rests on: base64, in-memory PNG encoding, and the HTML
// itself (self-contained, escaped, one image per data: URI, the means it claims to show).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "ndfmip/html_report.h"
#include "ndfmip/io.h"
#include "test_support.h"

using ndfmip::EvalReport;
using ndfmip::Image;
using ndfmip::ReportCase;
using ndfmip::test::TempDir;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
const std::string kDataPrefix = "data:image/png;base64,";

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

size_t countOf(const std::string& text, const std::string& needle) {
    size_t count = 0;
    for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
        ++count;
    return count;
}

// A decoder written independently of the encoder (bit accumulator, no lookup of groups).
std::string base64Decode(const std::string& text) {
    const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    unsigned bits = 0;
    int held = 0;
    for (char c : text) {
        if (c == '=') break;
        size_t v = alphabet.find(c);
        if (v == std::string::npos) ADD_FAILURE() << "not base64: " << c;
        bits = (bits << 6) | unsigned(v);
        held += 6;
        if (held >= 8) {
            held -= 8;
            out += char((bits >> held) & 0xFF);
        }
    }
    return out;
}

// The base64 payloads of every data: URI, in order.
std::vector<std::string> dataPayloads(const std::string& html) {
    std::vector<std::string> payloads;
    for (size_t at = html.find(kDataPrefix); at != std::string::npos;
         at = html.find(kDataPrefix, at + 1)) {
        size_t begin = at + kDataPrefix.size();
        payloads.push_back(html.substr(begin, html.find('"', begin) - begin));
    }
    return payloads;
}

// The page with the base64 payloads removed, so text searches cannot hit random letters in them.
std::string withoutPayloads(const std::string& html) {
    std::string out = html;
    for (const std::string& payload : dataPayloads(html))
        out.replace(out.find(payload), payload.size(), "");
    return out;
}

// Values k/levels (exact at that bit depth) plus the clamped extremes at fixed places.
Image rampImage(int w, int h, int c, int levels) {
    Image image(w, h, c);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = float((i * 7919 + 13) % size_t(levels + 1)) / float(levels);
    image.pixels[0] = -0.5f;
    image.pixels[1] = 1.5f;
    image.pixels[2] = std::numeric_limits<float>::quiet_NaN();
    return image;
}

Image flat(int w, int h, int c, float v) {
    Image image(w, h, c);
    std::fill(image.pixels.begin(), image.pixels.end(), v);
    return image;
}

ReportCase makeCase(const std::string& map, const std::string& method, const std::string& brdf,
                    int footprint, float exponent, float roughness, double relRmse,
                    double flicker) {
    ReportCase c;
    c.map = map;
    c.method = method;
    c.brdf = brdf;
    c.footprint = footprint;
    c.exponent = exponent;
    c.roughness = roughness;
    c.relRmse = relRmse;
    c.rmse = relRmse / 2;
    c.psnr = 40 - 10 * relRmse;
    c.energyRatio = 1 - relRmse / 10;
    c.flicker = flicker;
    return c;
}

struct Setting {
    const char* brdf;
    float exponent, roughness;
    double scale;
};
const Setting kSettings[] = {
    {"blinnphong", 8, 0, 1}, {"blinnphong", 64, 0, 3}, {"ggx", 0, 0.2f, 2}};
const char* const kMaps[] = {"rock", "cloth"};
const int kFootprints[] = {1, 4, 16};

double relRmseOf(int method, int map, const Setting& s, int footprint) {
    return 0.01 * (method + 1) * (map == 0 ? 1 : 5) * s.scale * std::sqrt(double(footprint));
}

// Two maps, three BRDF settings (two Blinn-Phong exponents), three footprints, two methods
// and the truth; one NaN rel. RMSE, one infinite PSNR, one NaN energy ratio; two image groups.
EvalReport sampleReport() {
    EvalReport report;
    report.title = "Maps <&> \"filters\"";
    report.notes = {"First note with <b>markup</b> & an ampersand.", "Second note."};
    const char* methods[] = {"naive", "toksvig"};
    for (int map = 0; map < 2; ++map)
        for (const Setting& s : kSettings)
            for (int f : kFootprints) {
                report.cases.push_back(makeCase(kMaps[map], "groundtruth", s.brdf, f, s.exponent,
                                                s.roughness, 0, 0.001 * f));
                for (int m = 0; m < 2; ++m)
                    report.cases.push_back(makeCase(kMaps[map], methods[m], s.brdf, f, s.exponent,
                                                    s.roughness, relRmseOf(m, map, s, f),
                                                    0.002 * f * (m + 1)));
            }
    for (ReportCase& c : report.cases) {
        if (c.method == "naive" && c.map == "cloth" && c.brdf == "ggx" && c.footprint == 16)
            c.relRmse = kNaN;
        if (c.method == "toksvig" && c.map == "rock" && c.footprint == 1 && c.exponent == 8) {
            c.psnr = kInf;
            c.energyRatio = kNaN;
        }
    }
    report.groups.push_back({"rock, blinnphong s = 8, footprint 4",
                             {{"truth", rampImage(8, 6, 3, 255)},
                              {"naive", flat(8, 6, 1, 0.25f)},
                              {"error <x>", rampImage(8, 6, 4, 255)}}});
    report.groups.push_back({"cloth", {{"truth", flat(4, 4, 3, 0.75f)}}});
    return report;
}

// The <td> texts of the row headed `rowHeader` in the section that starts at `heading`.
std::vector<std::string> rowCells(const std::string& html, const std::string& heading,
                                  const std::string& rowHeader) {
    size_t section = html.find(heading);
    size_t row = html.find("<tr><th>" + rowHeader + "</th>", section);
    if (section == std::string::npos || row == std::string::npos) return {};
    std::string text = html.substr(row, html.find("</tr>", row) - row);
    std::vector<std::string> cells;
    for (size_t at = text.find("<td"); at != std::string::npos; at = text.find("<td", at + 1)) {
        size_t open = text.find('>', at), close = text.find("</td>", at);
        if (open == std::string::npos || close == std::string::npos || close < open) break;
        std::string cell = text.substr(open + 1, close - open - 1);
        if (cell.find('<') == std::string::npos) cells.push_back(cell);
    }
    return cells;
}

std::string g4(double v) {
    char text[64];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

// Things no page may hold: printf's nan/inf inside SVG attributes, a NaN printed as "nan",
// and any reference to something outside the file.
void expectCleanPage(const std::string& html) {
    std::string text = withoutPayloads(html);
    std::string lower = text;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    auto wordChar = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (size_t at = lower.find("nan"); at != std::string::npos; at = lower.find("nan", at + 1)) {
        bool word = (at == 0 || !wordChar(lower[at - 1])) &&
                    (at + 3 >= lower.size() || !wordChar(lower[at + 3]));
        EXPECT_FALSE(word) << "a NaN printed as \"nan\" at " << at;
    }
    // No attribute value holds nan or inf (printf's output for non-finite coordinates).
    for (size_t at = lower.find("=\""); at != std::string::npos; at = lower.find("=\"", at + 2)) {
        size_t end = lower.find('"', at + 2);
        if (end == std::string::npos) break;
        std::string value = lower.substr(at + 2, end - at - 2);
        EXPECT_TRUE(value.find("nan") == std::string::npos &&
                    value.find("inf") == std::string::npos)
            << value;
        at = end;
    }
    EXPECT_EQ(text.find("http"), std::string::npos);
    EXPECT_EQ(text.find("url("), std::string::npos);
    EXPECT_EQ(text.find("<script"), std::string::npos);
    EXPECT_EQ(countOf(text, "src=\""), countOf(text, "src=\"data:image/png;base64,"));
    EXPECT_EQ(text.rfind("<!DOCTYPE html>", 0), 0u);
    EXPECT_NE(text.find("</html>"), std::string::npos);
}

} // namespace

TEST(Base64, MatchesRfc4648TestVectors) {
    EXPECT_EQ(ndfmip::base64Encode(""), "");
    EXPECT_EQ(ndfmip::base64Encode("f"), "Zg==");
    EXPECT_EQ(ndfmip::base64Encode("fo"), "Zm8=");
    EXPECT_EQ(ndfmip::base64Encode("foo"), "Zm9v");
    EXPECT_EQ(ndfmip::base64Encode("foob"), "Zm9vYg==");
    EXPECT_EQ(ndfmip::base64Encode("fooba"), "Zm9vYmE=");
    EXPECT_EQ(ndfmip::base64Encode("foobar"), "Zm9vYmFy");
}

TEST(Base64, HighBytesRoundTripThroughAnIndependentDecoder) {
    std::string bytes;
    for (int i = 0; i < 256; ++i) bytes += char(255 - i);
    for (size_t n = 0; n < 8; ++n)
        EXPECT_EQ(base64Decode(ndfmip::base64Encode(bytes.substr(0, n + 250))),
                  bytes.substr(0, n + 250));
}

TEST(EncodePng, RoundTripsThroughAFileAt8And16Bits) {
    TempDir dir("encode_png");
    for (int bits : {8, 16})
        for (int channels : {1, 3}) {
            int levels = bits == 8 ? 255 : 65535;
            Image image = rampImage(7, 5, channels, levels);
            auto bytes = ndfmip::encodePng(image, bits);
            ASSERT_TRUE(bytes) << bytes.error().message;
            EXPECT_EQ(bytes->substr(0, 8), "\x89PNG\r\n\x1A\n");
            std::string path =
                dir.file("b" + std::to_string(bits) + "c" + std::to_string(channels) + ".png");
            ASSERT_TRUE(ndfmip::writeFileAtomic(path, bytes.value()));
            auto loaded = ndfmip::loadImage(path);
            ASSERT_TRUE(loaded) << loaded.error().message;
            EXPECT_EQ(loaded->bitsPerChannel, bits);
            ASSERT_EQ(loaded->image.width, 7);
            ASSERT_EQ(loaded->image.height, 5);
            ASSERT_EQ(loaded->image.channels, channels);
            // Clamped: -0.5 -> 0, 1.5 -> 1, NaN -> 0; the rest are exact multiples of 1/levels.
            EXPECT_EQ(loaded->image.pixels[0], 0.f);
            EXPECT_EQ(loaded->image.pixels[1], 1.f);
            EXPECT_EQ(loaded->image.pixels[2], 0.f);
            for (size_t i = 3; i < image.pixels.size(); ++i)
                ASSERT_EQ(loaded->image.pixels[i], image.pixels[i]) << bits << " bits, value " << i;

            // savePng writes exactly the bytes encodePng makes.
            std::string saved = dir.file("saved.png");
            ASSERT_TRUE(ndfmip::savePng(saved, image, bits));
            EXPECT_EQ(readFile(saved), bytes.value());
        }
}

TEST(EncodePng, RejectsWhatPngCannotHold) {
    auto five = ndfmip::encodePng(Image(2, 2, 5), 8);
    ASSERT_FALSE(five);
    EXPECT_NE(five.error().message.find("1 to 4 channels"), std::string::npos);
    auto twelve = ndfmip::encodePng(Image(2, 2, 3), 12);
    ASSERT_FALSE(twelve);
    EXPECT_NE(twelve.error().message.find("8 or 16"), std::string::npos);
    EXPECT_FALSE(ndfmip::encodePng(Image(), 8));
    TempDir dir("encode_png_errors");
    ndfmip::Status status = ndfmip::savePng(dir.file("a.png"), Image(2, 2, 5), 8);
    EXPECT_EQ(status.error.rfind(dir.file("a.png") + ": cannot write (", 0), 0u) << status.error;
}

TEST(HtmlReport, EmbedsEveryImageAsAPngDataUri) {
    EvalReport report = sampleReport();
    std::string html = ndfmip::renderReportHtml(report);
    std::vector<std::string> payloads = dataPayloads(html);
    ASSERT_EQ(payloads.size(), 4u); // 3 + 1 images
    EXPECT_EQ(countOf(html, kDataPrefix), 4u);
    const Image& first = report.groups[0].images[0].display;
    auto png = ndfmip::encodePng(first, 8);
    ASSERT_TRUE(png);
    EXPECT_EQ(payloads[0], ndfmip::base64Encode(png.value()));
    std::string decoded = base64Decode(payloads[0]);
    EXPECT_EQ(decoded, png.value());

    // And the decoded bytes are the image.
    TempDir dir("report_image");
    ASSERT_TRUE(ndfmip::writeFileAtomic(dir.file("first.png"), decoded));
    auto loaded = ndfmip::loadImage(dir.file("first.png"));
    ASSERT_TRUE(loaded);
    ASSERT_EQ(loaded->image.pixels.size(), first.pixels.size());
    for (size_t i = 3; i < first.pixels.size(); ++i)
        EXPECT_EQ(loaded->image.pixels[i], first.pixels[i]);

    EXPECT_NE(html.find("image-rendering: pixelated"), std::string::npos);
    EXPECT_NE(html.find("<figcaption>error &lt;x&gt;</figcaption>"), std::string::npos);
    // An 8-pixel-wide image is shown at a whole multiple of its size: 160.
    EXPECT_NE(html.find("width=\"160\" alt=\"truth\""), std::string::npos);
}

TEST(HtmlReport, EscapesTextAndIsSelfContained) {
    std::string html = ndfmip::renderReportHtml(sampleReport());
    EXPECT_NE(html.find("<h1>Maps &lt;&amp;&gt; &quot;filters&quot;</h1>"), std::string::npos);
    EXPECT_EQ(html.find("<&>"), std::string::npos);
    EXPECT_NE(html.find("<p>First note with &lt;b&gt;markup&lt;/b&gt; &amp; an ampersand.</p>"),
              std::string::npos);
    EXPECT_EQ(html.find("<b>markup"), std::string::npos);
    for (const char* method : {"groundtruth", "naive", "toksvig"})
        EXPECT_NE(html.find(std::string("<th>") + method + "</th>"), std::string::npos) << method;
    expectCleanPage(html);
}

TEST(HtmlReport, DrawsOnePlotPerSettingAndPerFootprint) {
    std::string html = ndfmip::renderReportHtml(sampleReport());
    // 3 settings against footprint + 3 footprints against exponent (two exponents present).
    EXPECT_EQ(countOf(html, "<svg"), 6u);
    EXPECT_EQ(countOf(html, "</svg>"), 6u);
    // Each plot has one polyline per method (truth excluded), except the ggx plot where the
    // NaN at footprint 16 averages over the other map only and does not break the line.
    EXPECT_EQ(countOf(html, "<polyline"), 12u);
    EXPECT_NE(html.find("ggx, \xCE\xB1 = 0.2"), std::string::npos);
    EXPECT_NE(html.find("blinnphong, s = 64"), std::string::npos);
    EXPECT_NE(html.find("footprint (texels per pixel side)"), std::string::npos);
    EXPECT_NE(html.find("exponent s"), std::string::npos);
    // Distinct colours for the two methods.
    EXPECT_NE(html.find("stroke=\"#1f77b4\""), std::string::npos);
    EXPECT_NE(html.find("stroke=\"#d62728\""), std::string::npos);
}

TEST(HtmlReport, SummaryShowsGeometricMeansAndFlickerArithmeticMeans) {
    std::string html = ndfmip::renderReportHtml(sampleReport());
    EXPECT_NE(html.find("geometric mean"), std::string::npos);
    for (int m = 0; m < 2; ++m) {
        std::vector<std::string> cells =
            rowCells(html, "<h2>Summary</h2>", m == 0 ? "naive" : "toksvig");
        ASSERT_EQ(cells.size(), 3u);
        for (int fi = 0; fi < 3; ++fi) {
            double logSum = 0;
            int count = 0;
            for (int map = 0; map < 2; ++map)
                for (const Setting& s : kSettings) {
                    if (m == 0 && map == 1 && s.roughness > 0 && kFootprints[fi] == 16)
                        continue; // NaN
                    logSum += std::log(relRmseOf(m, map, s, kFootprints[fi]));
                    ++count;
                }
            EXPECT_EQ(cells[size_t(fi)], g4(std::exp(logSum / count))) << m << " " << fi;
        }
    }
    std::vector<std::string> truth = rowCells(html, "<h2>Flicker</h2>", "groundtruth");
    std::vector<std::string> toksvig = rowCells(html, "<h2>Flicker</h2>", "toksvig");
    ASSERT_EQ(truth.size(), 3u);
    ASSERT_EQ(toksvig.size(), 3u);
    for (int fi = 0; fi < 3; ++fi) {
        EXPECT_EQ(truth[size_t(fi)], g4(0.001 * kFootprints[fi]));
        EXPECT_EQ(toksvig[size_t(fi)], g4(0.004 * kFootprints[fi]));
    }
}

TEST(HtmlReport, ListsEveryCaseWithNonFiniteValuesSpelledOut) {
    EvalReport report = sampleReport();
    std::string html = ndfmip::renderReportHtml(report);
    size_t table = html.find("<h2>All cases</h2>");
    ASSERT_NE(table, std::string::npos);
    std::string all = html.substr(table, html.find("</table>", table) - table);
    EXPECT_EQ(countOf(all, "<tr><td>"), report.cases.size());
    EXPECT_NE(all.find("<td>inf</td>"), std::string::npos);          // PSNR of an exact case
    EXPECT_NE(all.find("<td>\xE2\x80\x93</td>"), std::string::npos); // NaN rel. RMSE
    EXPECT_NE(all.find("<td>\xC3\x97"
                       "0.998</td>"),
              std::string::npos); // energy 1 - 0.02/10
    expectCleanPage(html);
}

TEST(HtmlReport, HandlesNoCasesAndASingleFootprint) {
    EvalReport empty;
    empty.title = "Nothing";
    std::string html = ndfmip::renderReportHtml(empty);
    EXPECT_NE(html.find("No cases"), std::string::npos);
    EXPECT_EQ(countOf(html, "<svg"), 0u);
    expectCleanPage(html);

    EvalReport single;
    single.title = "One footprint, one exponent";
    single.cases.push_back(makeCase("rock", "groundtruth", "blinnphong", 4, 32, 0, 0, 0.01));
    single.cases.push_back(makeCase("rock", "naive", "blinnphong", 4, 32, 0, 0.1, 0.02));
    single.cases.push_back(makeCase("rock", "toksvig", "blinnphong", 4, 32, 0, kNaN, kInf));
    html = ndfmip::renderReportHtml(single);
    EXPECT_EQ(countOf(html, "<svg"), 1u);                    // against footprint only: one exponent
    EXPECT_EQ(countOf(html, "<circle"), 1u);                 // the NaN point is not drawn
    EXPECT_NE(html.find("<td>inf</td>"), std::string::npos); // toksvig's flicker mean
    expectCleanPage(html);

    // Every value NaN: the plot still has finite axes.
    single.cases[1].relRmse = kNaN;
    html = ndfmip::renderReportHtml(single);
    EXPECT_EQ(countOf(html, "<circle"), 0u);
    expectCleanPage(html);
}
