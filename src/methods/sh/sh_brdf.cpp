// Legendre coefficients of radially symmetric lobes (see sh_brdf.h and
// docs/SPHERICAL_HARMONICS.md).
#include "ndfmip/sh_brdf.h"

#include "core/quadrature.h"
#include "io/input_file.h"
#include "ndfmip/limits.h"

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ndfmip {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// Panel ends in theta over [0, pi]; see projectTransfer.
std::vector<double> panelEnds(int order, const std::vector<double>& breaks) {
    const double widest = std::min(kPiD / 16.0, 4.0 / (order + 1.0));
    const int uniform = int(std::ceil(kPiD / widest));
    std::vector<double> ends;
    for (int k = 0; k <= uniform; ++k) ends.push_back(k == uniform ? kPiD : kPiD * k / uniform);
    // Halving towards the peak of a sharp lobe at theta = 0, and from below towards the clamp
    // at pi/2, where max(t, 0)^s with a fractional s has a singular derivative.
    const double first = kPiD / uniform;
    for (int halving = 1; halving <= 40; ++halving) {
        ends.push_back(std::ldexp(first, -halving));
        ends.push_back(kPiD / 2.0 - std::ldexp(first, -halving));
    }
    ends.push_back(kPiD / 2.0);
    for (double b : breaks)
        if (b > 0.0 && b < kPiD) ends.push_back(b);
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    return ends;
}

std::string number(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

} // namespace

// ---- numeric projection ----------------------------------------------------------------------

std::vector<double> projectTransfer(const std::function<double(double)>& r, int order,
                                    const TransferProjectionOptions& options) {
    assert(order >= 0 && order <= kMaxTransferOrder);
    assert(options.nodesPerPanel >= 4);
    std::vector<double> nodes, weights;
    gaussLegendre(options.nodesPerPanel, nodes, weights);
    std::vector<double> a(order + 1, 0.0);
    const std::vector<double> ends = panelEnds(order, options.breaksRadians);
    for (size_t panel = 0; panel + 1 < ends.size(); ++panel) {
        const double half = 0.5 * (ends[panel + 1] - ends[panel]);
        const double middle = 0.5 * (ends[panel + 1] + ends[panel]);
        for (size_t i = 0; i < nodes.size(); ++i) {
            const double theta = middle + half * nodes[i];
            const double t = std::cos(theta);
            const double value = r(t);
            if (value == 0.0) continue; // most nodes of a sharp lobe: skip the recurrence
            const double weight = value * std::sin(theta) * half * weights[i];
            double previous = 1.0, current = t; // P_0, P_1
            a[0] += weight;
            if (order >= 1) a[1] += weight * t;
            for (int l = 1; l < order; ++l) {
                double next = ((2.0 * l + 1.0) * t * current - l * previous) / (l + 1.0);
                previous = current;
                current = next;
                a[l + 1] += weight * current;
            }
        }
    }
    for (double& coefficient : a) coefficient *= 2.0 * kPiD;
    return a;
}

// ---- lobes in double ---------------------------------------------------------------------------

double lambertTransfer(double t) {
    return t > 0.0 ? t / kPiD : 0.0;
}

double blinnPhongTransfer(double t, double s) {
    return t > 0.0 ? (s + 1.0) / (2.0 * kPiD) * std::pow(t, s) : 0.0;
}

double beckmannTransfer(double t, double alpha) {
    if (t <= 0.0) return 0.0;
    const double c2 = t * t, a2 = alpha * alpha;
    const double exponent = (1.0 - c2) / (c2 * a2); // tan^2 / a^2
    if (!(exponent < 700.0)) return 0.0;            // and no 0/0 where c2 underflows
    return std::exp(-exponent) / (kPiD * a2 * c2 * c2);
}

double ggxTransfer(double t, double alpha) {
    if (t <= 0.0) return 0.0;
    const double a2 = alpha * alpha;
    const double d = t * t * (a2 - 1.0) + 1.0;
    return a2 / (kPiD * d * d);
}

// ---- closed forms ------------------------------------------------------------------------------

std::vector<double> lambertCoefficients(int order) {
    assert(order >= 0 && order <= kMaxTransferOrder);
    std::vector<double> a(order + 1, 0.0);
    a[0] = 1.0;
    if (order >= 1) a[1] = 2.0 / 3.0;
    double central = 1.0; // l! / (2^l ((l/2)!)^2), by its ratio (l - 1)/l from l - 2
    for (int l = 2; l <= order; l += 2) {
        central *= (l - 1.0) / l;
        const double sign = (l / 2) % 2 == 1 ? 1.0 : -1.0; // (-1)^(l/2 - 1)
        a[l] = 2.0 * sign / ((l + 2.0) * (l - 1.0)) * central;
    }
    return a;
}

std::vector<double> blinnPhongCoefficients(double s, int order) {
    assert(order >= 0 && order <= kMaxTransferOrder);
    assert(std::isfinite(s) && s >= 0.0);
    std::vector<double> a(order + 1, 0.0);
    a[0] = 1.0;
    if (order >= 1) a[1] = (s + 1.0) / (s + 2.0);
    for (int l = 0; l + 2 <= order; ++l) a[l + 2] = a[l] * (s - l) / (s + l + 3.0);
    return a;
}

std::vector<double> blinnPhongApproxCoefficients(double s, int order) {
    assert(order >= 0 && order <= kMaxTransferOrder);
    assert(std::isfinite(s) && s > 0.0);
    std::vector<double> a(order + 1);
    for (int l = 0; l <= order; ++l) a[l] = std::exp(-double(l) * l / (2.0 * s));
    return a;
}

// ---- the renderer's materials ------------------------------------------------------------------

Result<std::vector<double>> brdfCoefficients(Brdf brdf, float exponent, float alpha, int order) {
    if (order < 0 || order > kMaxTransferOrder)
        return Error{"SH order " + std::to_string(order) + " outside [0, " +
                     std::to_string(kMaxTransferOrder) + "]"};
    const double s = exponent, a = alpha;
    switch (brdf) {
    case Brdf::Lambert:
        return lambertCoefficients(order);
    case Brdf::BlinnPhong:
        if (!(s > 0.0 && s <= 1e6))
            return Error{"Blinn-Phong exponent " + number(s) + " outside (0, 1e6]"};
        return blinnPhongCoefficients(s, order);
    case Brdf::Beckmann:
    case Brdf::Ggx: {
        if (!(a > 0.0 && a <= 1.0))
            return Error{std::string(brdfName(brdf)) + " roughness " + number(a) +
                         " outside (0, 1]"};
        if (brdf == Brdf::Beckmann)
            return projectTransfer([a](double t) { return beckmannTransfer(t, a); }, order);
        return projectTransfer([a](double t) { return ggxTransfer(t, a); }, order);
    }
    case Brdf::Tabulated:
        return Error{"a tabulated BRDF's coefficients come from its table (tabulatedCoefficients)"};
    }
    return Error{"unknown BRDF"};
}

// ---- truncation --------------------------------------------------------------------------------

double truncationEnergyLoss(const std::vector<double>& a, int order) {
    assert(order >= 0);
    double total = 0.0, tail = 0.0;
    for (size_t l = 0; l < a.size(); ++l) {
        double energy = (2.0 * l + 1.0) * a[l] * a[l];
        total += energy;
        if (int(l) > order) tail += energy;
    }
    return total > 0.0 ? tail / total : 0.0;
}

int orderNeeded(const std::vector<double>& a, double tolerance) {
    assert(!a.empty() && tolerance >= 0.0);
    double total = 0.0;
    for (size_t l = 0; l < a.size(); ++l) total += (2.0 * l + 1.0) * a[l] * a[l];
    // Walk down from the top, growing the tail until it would pass the tolerance.
    double tail = 0.0;
    for (int l = int(a.size()) - 1; l > 0; --l) {
        tail += (2.0 * l + 1.0) * a[l] * a[l];
        if (tail > tolerance * total) return l;
    }
    return 0;
}

Result<int> brdfOrderNeeded(Brdf brdf, float exponent, float alpha, double tolerance) {
    if (!(tolerance > 0.0 && tolerance < 1.0))
        return Error{"energy tolerance " + number(tolerance) + " outside (0, 1)"};
    for (int order = 64;; order = std::min(2 * order, kMaxTransferOrder)) {
        Result<std::vector<double>> a = brdfCoefficients(brdf, exponent, alpha, order);
        if (!a) return a.error();
        if (order == kMaxTransferOrder ||
            truncationEnergyLoss(a.value(), order / 2) <= 0.01 * tolerance)
            return orderNeeded(a.value(), tolerance);
    }
}

// ---- tabulated lobes ---------------------------------------------------------------------------

namespace {

bool parseNumber(const std::string& word, double& out) {
    const char* begin = word.data() + (word[0] == '+' ? 1 : 0); // from_chars takes no '+'
    const char* end = word.data() + word.size();
    auto [ptr, ec] = std::from_chars(begin, end, out);
    // from_chars reports out-of-range values (1e999) as errors; they are not numbers we can use.
    return ec == std::errc() && ptr == end;
}

// The value at an angle in degrees: linear between rows, 0 beyond the last.
double valueAtDegrees(const TabulatedTransfer& table, double degrees) {
    const std::vector<double>& x = table.anglesDegrees;
    if (x.empty() || !(degrees <= x.back())) return 0.0; // NaN lands here too
    if (degrees <= x.front()) return table.values.front();
    size_t upper = size_t(std::upper_bound(x.begin(), x.end(), degrees) - x.begin());
    if (upper >= x.size()) return table.values.back(); // exactly the last angle
    const double f = (degrees - x[upper - 1]) / (x[upper] - x[upper - 1]);
    return table.values[upper - 1] + f * (table.values[upper] - table.values[upper - 1]);
}

} // namespace

Result<TabulatedTransfer> loadTabulatedTransfer(const std::string& path) {
    Result<std::string> text = readRegularFile(path, inputLimits().maxTextFileBytes);
    if (!text) return text.error();
    return parseTabulatedTransfer(text.value(), path);
}

Result<TabulatedTransfer> parseTabulatedTransfer(const std::string& fileText,
                                                 const std::string& path) {
    std::istringstream in(fileText);
    TabulatedTransfer table;
    table.path = path;
    auto at = [&](int line, const std::string& problem) {
        return Error{path + ":" + std::to_string(line) + ": " + problem};
    };
    std::string text;
    bool header = false;
    for (int line = 1; std::getline(in, text); ++line) {
        std::istringstream words(text);
        std::vector<std::string> fields;
        for (std::string word; words >> word;) fields.push_back(word);
        if (fields.empty() || fields[0][0] == '#') continue;

        if (!header) {
            if (fields.size() != 2 ||
                (fields[0] != "theta_h_degrees" && fields[0] != "theta_d_degrees"))
                return at(line,
                          "expected the header 'theta_h_degrees NAME' or 'theta_d_degrees NAME'");
            table.angle = fields[0].substr(0, 7);
            table.valueName = fields[1];
            header = true;
            continue;
        }
        if (fields.size() != 2)
            return at(line,
                      "expected 'angle value', found " + std::to_string(fields.size()) + " fields");
        double angle = 0.0, value = 0.0;
        for (int k = 0; k < 2; ++k) {
            double& out = k == 0 ? angle : value;
            const char* what = k == 0 ? "angle" : "value";
            if (!parseNumber(fields[k], out))
                return at(line,
                          std::string(what) + " " + quote(fields[k], 32) + " is not a number");
            if (std::isnan(out)) return at(line, std::string(what) + " is NaN");
            if (!std::isfinite(out)) return at(line, std::string(what) + " is infinite");
        }
        if (angle < 0.0 || angle > 90.0)
            return at(line, "angle " + shortened(fields[0], 32) + " outside [0, 90] degrees");
        if (value < 0.0) return at(line, "negative value " + shortened(fields[1], 32));
        if (table.anglesDegrees.empty() && angle != 0.0)
            return at(line, "the first angle must be 0, found " + shortened(fields[0], 32));
        if (!table.anglesDegrees.empty() && angle <= table.anglesDegrees.back())
            return at(line, "angle " + shortened(fields[0], 32) + " does not increase (previous " +
                                number(table.anglesDegrees.back()) + ")");
        table.anglesDegrees.push_back(angle);
        table.values.push_back(value);
    }
    if (!header) return Error{path + ": no header line (empty file?)"};
    if (table.values.size() < 2)
        return Error{path + ": " + std::to_string(table.values.size()) +
                     (table.values.size() == 1 ? " data row" : " data rows") +
                     ", at least 2 are needed"};
    return table;
}

double evaluate(const TabulatedTransfer& table, double t) {
    if (std::isnan(t)) return 0.0;
    return valueAtDegrees(table, std::acos(std::clamp(t, -1.0, 1.0)) * (180.0 / kPiD));
}

double tabulatedFactor(const TabulatedTransfer& g, double thetaD) {
    return valueAtDegrees(g, thetaD * (180.0 / kPiD));
}

Result<std::vector<double>> tabulatedCoefficients(const TabulatedTransfer& f, int order) {
    if (f.angle != "theta_h")
        return Error{
            f.path + ": a " + f.angle +
            " table is a factor applied after filtering; only theta_h tables are projected"};
    if (order < 0 || order > kMaxTransferOrder)
        return Error{"SH order " + std::to_string(order) + " outside [0, " +
                     std::to_string(kMaxTransferOrder) + "]"};
    TransferProjectionOptions options;
    for (double degrees : f.anglesDegrees)
        options.breaksRadians.push_back(degrees * (kPiD / 180.0));
    return projectTransfer([&f](double t) { return evaluate(f, t); }, order, options);
}

} // namespace ndfmip
