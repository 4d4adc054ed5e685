// The evaluation report: one HTML page that holds everything it shows (tables of the numbers,
// SVG plots, the images as base64 PNGs, its CSS), so it opens from disk in any browser and
// can be mailed or archived as a single file.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "ndfmip/image.h"

namespace ndfmip {

struct ReportImage {
    std::string label;
    Image display; // display-ready RGB(A) (or grey) values in [0,1]
};

// One row of the results: a method in one setting.
struct ReportCase {
    std::string map, method, brdf; // brdf: "blinnphong", "beckmann", "ggx", "lambert"
    int footprint = 1;             // texels per pixel side (1, 4, 16, 64, ...)
    float exponent = 0;            // Blinn-Phong s, or 0 when not applicable
    float roughness = 0;           // base alpha for beckmann/ggx, else 0
    double relRmse = 0, rmse = 0, psnr = 0, energyRatio = 0, flicker = 0;
};

// One setting: images side by side (truth, methods, error images).
struct ReportGroup {
    std::string title;
    std::vector<ReportImage> images;
};

struct EvalReport {
    std::string title;
    std::vector<std::string> notes; // paragraphs shown under the title (plain text)
    std::string liveView; // an HTML section shown after the summary (the WebGL2 view), or empty
    std::vector<ReportCase> cases; // method "groundtruth" rows carry the truth's own flicker
    std::vector<ReportGroup> groups;
};

// The whole report as one HTML document with no external references. All text is escaped;
// NaN prints as "–" and infinities as "inf".
std::string renderReportHtml(const EvalReport& report);

// Text as HTML shows it: & < > " ' escaped.
std::string escapeHtml(std::string_view text);

// Standard base64 (RFC 4648, with '=' padding).
std::string base64Encode(const std::string& bytes);

} // namespace ndfmip
