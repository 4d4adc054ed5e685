// The evaluation report page. Everything is written inline (CSS, SVG plots, PNGs as data:
// URIs) so the page needs nothing beside it; the plots are drawn here rather than by a
// script so they show with JavaScript off and survive being archived.
#include "ndfmip/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <map>
#include <string_view>
#include <tuple>
#include <utility>

#include "ndfmip/io.h"

namespace ndfmip {

std::string escapeHtml(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        case '\'':
            out += "&#39;";
            break;
        default:
            out += c;
        }
    }
    return out;
}

namespace {

const char* const kGroundTruth = "groundtruth";

// Fixed colours, one per method (the truth aside) in order of first appearance (Tableau 10).
const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};

// `digits` significant digits (or decimals when `fixed`); NaN as an en dash, infinities as
// "inf" so a diverging method reads as such instead of as printf's "nan".
std::string formatNumber(double value, int digits, bool fixed = false) {
    if (std::isnan(value)) return "\xE2\x80\x93";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    char text[64];
    std::snprintf(text, sizeof text, fixed ? "%.*f" : "%.*g", digits, value);
    return text;
}

std::string coord(double v) {
    return formatNumber(v, 1, true);
}

// ---- grouping the cases -----------------------------------------------------------------------

// A BRDF with its parameter: the unit the plots of rel. RMSE against footprint are drawn for.
struct Setting {
    int brdfRank = 0; // order of first appearance of the BRDF name
    float exponent = 0, roughness = 0;
    auto key() const { return std::tuple(brdfRank, exponent, roughness); }
    bool operator<(const Setting& other) const { return key() < other.key(); }
};

std::string formatParameter(float v) {
    return formatNumber(double(v), 4);
}

std::string settingParameter(const ReportCase& c) {
    std::string text;
    if (c.exponent > 0) text += "s = " + formatParameter(c.exponent);
    if (c.roughness > 0)
        text +=
            (text.empty() ? "" : ", ") + std::string("\xCE\xB1 = ") + formatParameter(c.roughness);
    return text;
}

// Names in order of first appearance, for rows, legends and colours that follow the input.
struct Ranks {
    std::vector<std::string> names;
    int of(const std::string& name) {
        auto it = std::find(names.begin(), names.end(), name);
        if (it != names.end()) return int(it - names.begin());
        names.push_back(name);
        return int(names.size()) - 1;
    }
};

// Rel. RMSE is a ratio whose size changes by orders of magnitude between settings, so the
// summaries take the geometric mean (exp of the mean log); flicker takes the arithmetic one.
// NaN values (no data) are skipped; a zero makes the geometric mean zero, an inf makes it inf.
struct Mean {
    double sum = 0, logSum = 0;
    int count = 0;
    void add(double v) {
        if (std::isnan(v)) return;
        sum += v;
        logSum += std::log(v);
        ++count;
    }
    double arithmetic() const { return count ? sum / count : std::nan(""); }
    double geometric() const { return count ? std::exp(logSum / count) : std::nan(""); }
};

struct Digest {
    Ranks methods, brdfs, maps;
    std::vector<int> footprints;             // sorted, distinct
    std::vector<float> exponents;            // Blinn-Phong exponents, sorted, distinct
    std::map<Setting, std::string> settings; // -> label
};

Digest digest(const EvalReport& report) {
    Digest d;
    for (const ReportCase& c : report.cases) {
        d.methods.of(c.method);
        d.maps.of(c.map);
        Setting s{d.brdfs.of(c.brdf), c.exponent, c.roughness};
        std::string parameter = settingParameter(c);
        d.settings.emplace(s, c.brdf + (parameter.empty() ? "" : ", " + parameter));
        d.footprints.push_back(c.footprint);
        if (c.brdf == "blinnphong" && c.method != kGroundTruth) d.exponents.push_back(c.exponent);
    }
    std::sort(d.footprints.begin(), d.footprints.end());
    d.footprints.erase(std::unique(d.footprints.begin(), d.footprints.end()), d.footprints.end());
    std::sort(d.exponents.begin(), d.exponents.end());
    d.exponents.erase(std::unique(d.exponents.begin(), d.exponents.end()), d.exponents.end());
    return d;
}

std::string methodColour(size_t index) {
    return kPalette[index % std::size(kPalette)];
}

// ---- SVG line plots ---------------------------------------------------------------------------

struct Series {
    std::string name, colour;
    std::vector<std::pair<double, double>> points; // (x, y), x ascending
};

struct PlotLabels {
    std::string title, xLabel, yLabel;
};

// One axis: data values to pixels, linearly or in log10 space (lo/hi are in that space).
struct Axis {
    bool log = false;
    double lo = 0, hi = 1, pixelLo = 0, pixelHi = 1;
    double toPixel(double v) const {
        double t = ((log ? std::log10(v) : v) - lo) / (hi - lo);
        return pixelLo + t * (pixelHi - pixelLo);
    }
};

double niceStep(double span) {
    double magnitude = std::pow(10.0, std::floor(std::log10(span)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * magnitude >= span) return m * magnitude;
    return 10 * magnitude;
}

// Linear from zero, or log10 by whole decades when all values are positive and span over 30x.
Axis valueAxis(const std::vector<double>& values, std::vector<double>& ticks) {
    Axis axis;
    if (values.empty()) {
        ticks = {0, 0.5, 1};
        return axis;
    }
    auto [minIt, maxIt] = std::minmax_element(values.begin(), values.end());
    double lo = *minIt, hi = *maxIt;
    if (lo > 0 && hi / lo > 30) {
        axis.log = true;
        axis.lo = std::floor(std::log10(lo));
        axis.hi = std::ceil(std::log10(hi));
        for (double e = axis.lo; e <= axis.hi + 0.5; ++e) ticks.push_back(std::pow(10.0, e));
        return axis;
    }
    double step = niceStep(std::max(hi - std::min(lo, 0.0), 1e-300) / 4);
    if (hi <= 0 && lo >= 0) step = 0.25; // all zero
    axis.lo = std::min(0.0, std::floor(lo / step) * step);
    axis.hi = std::max(axis.lo + step, std::ceil(hi / step) * step);
    for (double t = axis.lo; t <= axis.hi + step / 2; t += step) ticks.push_back(t);
    return axis;
}

std::string svgText(double x, double y, const std::string& text, const char* anchor,
                    const std::string& extra = "") {
    return "<text x=\"" + coord(x) + "\" y=\"" + coord(y) + "\" text-anchor=\"" + anchor + "\"" +
           extra + ">" + escapeHtml(text) + "</text>";
}

// A line plot with log x (ticks at the x values present), a legend on the right and one
// polyline per series; non-finite points break the line and are not drawn.
std::string svgLinePlot(const PlotLabels& labels, const std::vector<Series>& series) {
    std::vector<double> xs, ys;
    for (const Series& s : series)
        for (auto [x, y] : s.points) {
            if (!(x > 0) || !std::isfinite(x) || !std::isfinite(y)) continue;
            xs.push_back(x);
            ys.push_back(y);
        }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());

    const double left = 60, plotRight = 300, top = 30, legendX = 316;
    const double width = 440, height = std::max(240.0, top + 18.0 * double(series.size()) + 20);
    const double bottom = height - 46;
    Axis x{true, 0, 1, left, plotRight};
    if (!xs.empty()) {
        x.lo = std::log10(xs.front());
        x.hi = std::log10(xs.back());
    }
    double pad = x.hi > x.lo ? (x.hi - x.lo) * 0.06 : 0.5; // one footprint: centre it
    x.lo -= pad;
    x.hi += pad;
    std::vector<double> yTicks;
    Axis y = valueAxis(ys, yTicks);
    y.pixelLo = bottom;
    y.pixelHi = top;

    std::string svg = "<svg class=\"plot\" width=\"" + coord(width) + "\" height=\"" +
                      coord(height) + "\" viewBox=\"0 0 " + coord(width) + " " + coord(height) +
                      "\" role=\"img\" font-size=\"11\">";
    svg += svgText(left + (plotRight - left) / 2, 16, labels.title, "middle",
                   " font-weight=\"bold\" font-size=\"12\"");
    svg += "<rect x=\"" + coord(left) + "\" y=\"" + coord(top) + "\" width=\"" +
           coord(plotRight - left) + "\" height=\"" + coord(bottom - top) +
           "\" fill=\"none\" stroke=\"#888\"/>";
    for (double t : yTicks) {
        double py = y.toPixel(t);
        svg += "<line x1=\"" + coord(left) + "\" x2=\"" + coord(plotRight) + "\" y1=\"" +
               coord(py) + "\" y2=\"" + coord(py) + "\" stroke=\"#e4e4e4\"/>";
        svg += svgText(left - 5, py + 4, formatNumber(t, 3), "end");
    }
    for (double t : xs) {
        double px = x.toPixel(t);
        svg += "<line x1=\"" + coord(px) + "\" x2=\"" + coord(px) + "\" y1=\"" + coord(bottom) +
               "\" y2=\"" + coord(bottom + 4) + "\" stroke=\"#888\"/>";
        svg += svgText(px, bottom + 16, formatNumber(t, 4), "middle");
    }
    svg += svgText(left + (plotRight - left) / 2, height - 8, labels.xLabel, "middle");
    svg += svgText(0, 0, labels.yLabel, "middle",
                   " transform=\"translate(14 " + coord((top + bottom) / 2) + ") rotate(-90)\"");

    for (size_t i = 0; i < series.size(); ++i) {
        const Series& s = series[i];
        std::string line, dots;
        auto flush = [&] {
            if (!line.empty())
                svg += "<polyline fill=\"none\" stroke=\"" + s.colour +
                       "\" stroke-width=\"1.8\" points=\"" + line + "\"/>";
            line.clear();
        };
        for (auto [px, py] : s.points) {
            if (!(px > 0) || !std::isfinite(px) || !std::isfinite(py)) {
                flush();
                continue;
            }
            std::string at = coord(x.toPixel(px)) + "," + coord(y.toPixel(py));
            line += (line.empty() ? "" : " ") + at;
            dots += "<circle cx=\"" + coord(x.toPixel(px)) + "\" cy=\"" + coord(y.toPixel(py)) +
                    "\" r=\"2.6\" fill=\"" + s.colour + "\"/>";
        }
        flush();
        svg += dots;
        double ly = top + 8 + 18.0 * double(i);
        svg += "<line x1=\"" + coord(legendX) + "\" x2=\"" + coord(legendX + 20) + "\" y1=\"" +
               coord(ly) + "\" y2=\"" + coord(ly) + "\" stroke=\"" + s.colour +
               "\" stroke-width=\"2\"/>";
        svg += svgText(legendX + 26, ly + 4, s.name, "start");
    }
    return svg + "</svg>";
}

// ---- page sections ----------------------------------------------------------------------------

// Rows: methods; columns: footprints; cells from `cell(method, footprint)`. The lowest finite
// value of each column is bold when `markBest`.
template <class Cell>
std::string methodFootprintTable(const std::vector<std::string>& methods,
                                 const std::vector<int>& footprints, const std::string& caption,
                                 bool markBest, Cell cell) {
    std::vector<std::vector<double>> values(methods.size());
    for (size_t m = 0; m < methods.size(); ++m)
        for (int f : footprints) values[m].push_back(cell(methods[m], f));
    std::string html = "<table class=\"numbers\"><caption>" + escapeHtml(caption) +
                       "</caption><thead><tr><th>method</th>";
    for (int f : footprints) html += "<th>footprint " + std::to_string(f) + "</th>";
    html += "</tr></thead><tbody>";
    for (size_t m = 0; m < methods.size(); ++m) {
        html += "<tr><th>" + escapeHtml(methods[m]) + "</th>";
        for (size_t f = 0; f < footprints.size(); ++f) {
            double v = values[m][f];
            bool best = markBest && std::isfinite(v);
            for (size_t other = 0; best && other < methods.size(); ++other)
                best = !(values[other][f] < v);
            html += best ? "<td class=\"best\">" : "<td>";
            html += formatNumber(v, 4) + "</td>";
        }
        html += "</tr>";
    }
    return html + "</tbody></table>";
}

std::string allCasesTable(const EvalReport& report, Digest& d) {
    std::vector<const ReportCase*> rows;
    for (const ReportCase& c : report.cases) rows.push_back(&c);
    auto key = [&](const ReportCase* c) {
        return std::tuple(d.maps.of(c->map), d.brdfs.of(c->brdf), c->exponent, c->roughness,
                          c->footprint, d.methods.of(c->method));
    };
    std::stable_sort(rows.begin(), rows.end(),
                     [&](const ReportCase* a, const ReportCase* b) { return key(a) < key(b); });
    std::string html =
        "<table class=\"numbers all\"><caption>Every case (energy ratio: mean shaded / mean "
        "truth)</caption><thead><tr><th>map</th><th>method</th><th>BRDF</th><th>parameter</th>"
        "<th>footprint</th><th>rel. RMSE</th><th>RMSE</th><th>PSNR (dB)</th><th>energy</th>"
        "<th>flicker</th></tr></thead><tbody>";
    for (const ReportCase* c : rows) {
        std::string parameter = settingParameter(*c);
        html +=
            "<tr><td>" + escapeHtml(c->map) + "</td><td>" + escapeHtml(c->method) + "</td><td>" +
            escapeHtml(c->brdf) + "</td><td>" +
            (parameter.empty() ? "\xE2\x80\x93" : escapeHtml(parameter)) + "</td><td>" +
            std::to_string(c->footprint) + "</td><td>" + formatNumber(c->relRmse, 4) + "</td><td>" +
            formatNumber(c->rmse, 4) + "</td><td>" + formatNumber(c->psnr, 2, true) + "</td><td>" +
            (std::isnan(c->energyRatio) ? "" : "\xC3\x97") + formatNumber(c->energyRatio, 3, true) +
            "</td><td>" + formatNumber(c->flicker, 4) + "</td></tr>";
    }
    return html + "</tbody></table>";
}

// (a) rel. RMSE against footprint, one plot per setting; (b) against the Blinn-Phong exponent,
// one plot per footprint. Both average over maps (geometric mean).
std::string plots(const EvalReport& report, Digest& d) {
    std::vector<std::string> methods;
    for (const std::string& m : d.methods.names)
        if (m != kGroundTruth) methods.push_back(m);
    if (methods.empty()) return "";
    auto seriesFrom = [&](const std::map<std::pair<int, double>, Mean>& means) {
        std::vector<Series> series;
        for (size_t i = 0; i < methods.size(); ++i) {
            int rank = d.methods.of(methods[i]);
            Series s{methods[i], methodColour(i), {}};
            for (const auto& [at, mean] : means)
                if (at.first == rank) s.points.emplace_back(at.second, mean.geometric());
            series.push_back(std::move(s));
        }
        return series;
    };

    std::string html = "<h2>Rel. RMSE against footprint</h2><p class=\"caption\">One plot per "
                       "BRDF setting; geometric mean over maps.</p><div class=\"plots\">";
    for (const auto& [setting, label] : d.settings) {
        std::map<std::pair<int, double>, Mean> means; // (method rank, footprint)
        for (const ReportCase& c : report.cases)
            if (c.method != kGroundTruth &&
                Setting{d.brdfs.of(c.brdf), c.exponent, c.roughness}.key() == setting.key())
                means[{d.methods.of(c.method), double(c.footprint)}].add(c.relRmse);
        if (means.empty()) continue; // a setting with only the truth's own rows
        html += svgLinePlot({label, "footprint (texels per pixel side)", "rel. RMSE"},
                            seriesFrom(means));
    }
    html += "</div>";

    if (d.exponents.size() < 2) return html;
    html += "<h2>Rel. RMSE against Blinn-Phong exponent</h2><p class=\"caption\">One plot per "
            "footprint; geometric mean over maps.</p><div class=\"plots\">";
    for (int f : d.footprints) {
        std::map<std::pair<int, double>, Mean> means; // (method rank, exponent)
        for (const ReportCase& c : report.cases)
            if (c.method != kGroundTruth && c.brdf == "blinnphong" && c.footprint == f)
                means[{d.methods.of(c.method), double(c.exponent)}].add(c.relRmse);
        if (means.empty()) continue;
        html += svgLinePlot({"footprint " + std::to_string(f), "exponent s", "rel. RMSE"},
                            seriesFrom(means));
    }
    return html + "</div>";
}

int displayWidth(int width) {
    if (width >= 160) return std::min(width, 320);
    return width * std::max(1, 160 / width); // whole multiples keep pixelated texels square
}

std::string imageGroups(const EvalReport& report) {
    std::string html;
    for (const ReportGroup& group : report.groups) {
        html += "<section class=\"group\"><h3>" + escapeHtml(group.title) +
                "</h3><div class=\"images\">";
        for (const ReportImage& image : group.images) {
            html += "<figure>";
            auto png = encodePng(image.display, 8);
            if (png)
                html += "<img src=\"data:image/png;base64," + base64Encode(png.value()) +
                        "\" width=\"" + std::to_string(displayWidth(image.display.width)) +
                        "\" alt=\"" + escapeHtml(image.label) + "\">";
            else
                html += "<div class=\"missing\">" + escapeHtml(png.error().message) + "</div>";
            html += "<figcaption>" + escapeHtml(image.label) + "</figcaption></figure>";
        }
        html += "</div></section>";
    }
    return html;
}

const char* const kStyle = R"(
body { font-family: system-ui, sans-serif; margin: 24px; color: #222; max-width: 1400px; }
h1 { font-size: 22px; } h2 { font-size: 17px; margin-top: 32px; } h3 { font-size: 14px; }
p.caption, caption { color: #555; font-size: 13px; text-align: left; padding: 4px 0; }
table.numbers { border-collapse: collapse; font-size: 13px; margin: 8px 0 16px; }
table.numbers th, table.numbers td { border: 1px solid #ddd; padding: 3px 8px; }
table.numbers td { text-align: right; font-variant-numeric: tabular-nums; }
table.numbers thead th { background: #f3f3f3; }
table.all td:nth-child(-n+4) { text-align: left; }
td.best { font-weight: bold; }
.plots, .images { display: flex; flex-wrap: wrap; gap: 12px; align-items: flex-start; }
svg.plot { border: 1px solid #eee; }
figure { margin: 0; text-align: center; font-size: 12px; }
figure img { image-rendering: pixelated; height: auto; display: block; }
figcaption { margin-top: 4px; max-width: 320px; word-wrap: break-word; }
.missing { width: 160px; height: 160px; background: #fee; font-size: 11px; }
)";

} // namespace

std::string base64Encode(const std::string& bytes) {
    static const char alphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 |
                     uint8_t(bytes[i + 2]);
        for (int shift : {18, 12, 6, 0}) out += alphabet[(v >> shift) & 63];
    }
    size_t rest = bytes.size() - i;
    if (rest > 0) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (rest == 2) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += rest == 2 ? alphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string renderReportHtml(const EvalReport& report) {
    Digest d = digest(report);
    std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
                       escapeHtml(report.title) + "</title><style>" + kStyle +
                       "</style></head><body><h1>" + escapeHtml(report.title) + "</h1>";
    for (const std::string& note : report.notes) html += "<p>" + escapeHtml(note) + "</p>";

    if (report.cases.empty()) {
        html += "<p>No cases were evaluated.</p>";
    } else {
        std::vector<std::string> methods, withTruth;
        for (const std::string& m : d.methods.names)
            (m == kGroundTruth ? withTruth : methods).push_back(m);
        withTruth.insert(withTruth.begin(), methods.begin(), methods.end());
        auto meanOf = [&](double ReportCase::*field, bool geometric) {
            return [&report, field, geometric](const std::string& method, int footprint) {
                Mean mean;
                for (const ReportCase& c : report.cases)
                    if (c.method == method && c.footprint == footprint) mean.add(c.*field);
                return geometric ? mean.geometric() : mean.arithmetic();
            };
        };
        html += "<h2>Summary</h2>";
        if (!methods.empty())
            html += methodFootprintTable(
                methods, d.footprints,
                "Rel. RMSE: geometric mean over maps and BRDF settings (lowest in bold)", true,
                meanOf(&ReportCase::relRmse, true));
        html += plots(report, d);
        html += report.liveView;
        html += "<h2>Flicker</h2>";
        html += methodFootprintTable(withTruth, d.footprints,
                                     "Flicker: arithmetic mean over maps and BRDF settings; the "
                                     "groundtruth row is the truth's own flicker",
                                     false, meanOf(&ReportCase::flicker, false));
        html += "<h2>All cases</h2>" + allCasesTable(report, d);
    }
    if (!report.groups.empty()) html += "<h2>Images</h2>" + imageGroups(report);
    return html + "</body></html>\n";
}

} // namespace ndfmip
