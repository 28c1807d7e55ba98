#include "converge_report.hpp"

#include "effigi/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace effigi::app {

namespace {

double errorOf(const Checkpoint& c, bool estimate) { return estimate ? c.estimatedRelMSE : c.relMSE; }

std::string escape(const std::string& s) {
    std::string r;
    for (char c : s) {
        if (c == '<') r += "&lt;";
        else if (c == '>') r += "&gt;";
        else if (c == '&') r += "&amp;";
        else if (c == '"') r += "&quot;";
        else r += c;
    }
    return r;
}

const char* colour(std::size_t i) {
    static const char* palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};
    return palette[i % (sizeof palette / sizeof *palette)];
}

} // namespace

double fittedSlope(const std::vector<Checkpoint>& cps, bool useEstimate, std::uint64_t minSpp) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const auto& c : cps) {
        double e = errorOf(c, useEstimate);
        if (c.spp < minSpp || !(e > 0.0) || !std::isfinite(e) || !(c.seconds > 0.0)) continue;
        double x = std::log(c.seconds), y = std::log(e);
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
    }
    if (n < 2) return std::nan("");
    double den = n * sxx - sx * sx;
    return den != 0.0 ? (n * sxy - sx * sy) / den : std::nan("");
}

void writeCSV(const std::filesystem::path& file, const std::vector<ConfigurationRun>& runs) {
    std::ofstream out(file);
    if (!out) fail("cannot write {}", file.string());
    out << "configuration,spp,samples,seconds,rmse,relmse,mae,nan_fraction,estimated_relmse\n";
    auto num = [](double v) { return v < 0.0 ? std::string() : fmt::format("{:.6g}", v); };
    for (const auto& r : runs)
        for (const auto& c : r.checkpoints)
            out << r.name << ',' << c.spp << ',' << c.samples << ',' << fmt::format("{:.6f}", c.seconds) << ','
                << num(c.rmse) << ',' << num(c.relMSE) << ',' << num(c.mae) << ',' << fmt::format("{:.6g}", c.nanFraction)
                << ',' << num(c.estimatedRelMSE) << '\n';
    if (!out) fail("cannot write {}", file.string());
}

std::string plotSVG(const std::vector<ConfigurationRun>& runs, bool haveReference) {
    // Axes span the data, rounded out to powers of ten.
    double tMin = 1e300, tMax = 0, eMin = 1e300, eMax = 0;
    for (const auto& r : runs)
        for (const auto& c : r.checkpoints) {
            double e = haveReference ? c.relMSE : c.estimatedRelMSE;
            if (!(c.seconds > 0.0) || !(e > 0.0) || !std::isfinite(e)) continue;
            tMin = std::min(tMin, c.seconds), tMax = std::max(tMax, c.seconds);
            eMin = std::min(eMin, e), eMax = std::max(eMax, e);
        }
    if (tMax == 0) tMin = 0.1, tMax = 1, eMin = 1e-3, eMax = 1;
    double lx0 = std::floor(std::log10(tMin)), lx1 = std::ceil(std::log10(tMax));
    double ly0 = std::floor(std::log10(eMin)), ly1 = std::ceil(std::log10(eMax));
    if (lx1 == lx0) lx1 += 1;
    if (ly1 == ly0) ly1 += 1;
    const double W = 640, H = 420, L = 70, R = 20, T = 20, B = 50;
    auto px = [&](double t) { return L + (std::log10(t) - lx0) / (lx1 - lx0) * (W - L - R); };
    auto py = [&](double e) { return H - B - (std::log10(e) - ly0) / (ly1 - ly0) * (H - T - B); };

    std::string s = fmt::format(R"~(<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}" font-family="sans-serif" font-size="12">)~"
                                "\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
                                W, H, W, H);
    for (double d = lx0; d <= lx1; d += 1)
        s += fmt::format(R"~(<line x1="{0:.1f}" y1="{1}" x2="{0:.1f}" y2="{2}" stroke="#ddd"/><text x="{0:.1f}" y="{3}" text-anchor="middle">1e{4}</text>)~"
                         "\n",
                         px(std::pow(10, d)), T, H - B, H - B + 16, int(d));
    for (double d = ly0; d <= ly1; d += 1)
        s += fmt::format(R"~(<line x1="{0}" y1="{1:.1f}" x2="{2}" y2="{1:.1f}" stroke="#ddd"/><text x="{3}" y="{4:.1f}" text-anchor="end">1e{5}</text>)~"
                         "\n",
                         L, py(std::pow(10, d)), W - R, L - 6, py(std::pow(10, d)) + 4, int(d));
    s += fmt::format(R"~(<text x="{}" y="{}" text-anchor="middle">time [s]</text>)~"
                     "\n",
                     (L + W - R) / 2, H - 12);
    s += fmt::format(R"~(<text transform="translate(16 {}) rotate(-90)" text-anchor="middle">{}</text>)~"
                     "\n",
                     (T + H - B) / 2, haveReference ? "relMSE against the reference" : "estimated relMSE");
    for (std::size_t i = 0; i < runs.size(); ++i) {
        std::string points;
        for (const auto& c : runs[i].checkpoints) {
            double e = haveReference ? c.relMSE : c.estimatedRelMSE;
            if (c.seconds > 0.0 && e > 0.0 && std::isfinite(e)) points += fmt::format("{:.1f},{:.1f} ", px(c.seconds), py(e));
        }
        s += fmt::format(R"~(<polyline fill="none" stroke="{}" stroke-width="2" points="{}"/>)~"
                         "\n",
                         colour(i), points);
        double slope = fittedSlope(runs[i].checkpoints, !haveReference);
        s += fmt::format(R"~(<rect x="{}" y="{}" width="14" height="3" fill="{}"/><text x="{}" y="{}">{} (slope {:.2f})</text>)~"
                         "\n",
                         W - R - 230, T + 10 + 16 * i, colour(i), W - R - 210, T + 14 + 16 * i, escape(runs[i].name), slope);
    }
    return s + "</svg>\n";
}

void writeHTML(const std::filesystem::path& file, const std::string& sceneName, const std::vector<ConfigurationRun>& runs,
               bool haveReference, const std::string& svg) {
    std::ofstream out(file);
    if (!out) fail("cannot write {}", file.string());
    // Polyglot markup (valid HTML5 that is also well-formed XML), so tests can parse it.
    out << "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>effigi converge: "
        << escape(sceneName) << "</title>\n"
        << "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
           "td,th{border:1px solid #ccc;padding:4px 8px;text-align:right}img{image-rendering:pixelated;width:256px}"
           "figure{display:inline-block;margin:0 1em 1em 0}</style>\n</head>\n<body>\n"
        << "<h1>Error against time: " << escape(sceneName) << "</h1>\n"
        << svg
        << "<h2>Final checkpoint</h2>\n<table>\n<tr><th>configuration</th><th>spp</th><th>seconds</th>"
           "<th>RMSE</th><th>relMSE</th><th>estimated relMSE</th><th>fitted slope</th></tr>\n";
    auto num = [](double v) { return v < 0.0 ? std::string("&ndash;") : fmt::format("{:.4g}", v); };
    for (const auto& r : runs) {
        if (r.checkpoints.empty()) continue;
        const Checkpoint& c = r.checkpoints.back();
        out << "<tr><td style=\"text-align:left\">" << escape(r.name) << "</td><td>" << c.spp << "</td><td>"
            << fmt::format("{:.2f}", c.seconds) << "</td><td>" << num(c.rmse) << "</td><td>" << num(c.relMSE)
            << "</td><td>" << num(c.estimatedRelMSE) << "</td><td>"
            << fmt::format("{:.2f}", fittedSlope(r.checkpoints, !haveReference)) << "</td></tr>\n";
    }
    out << "</table>\n<h2>Images</h2>\n";
    for (const auto& r : runs) {
        if (!r.image.empty())
            out << "<figure><img src=\"" << escape(r.image) << "\" alt=\"" << escape(r.name) << "\"/><figcaption>"
                << escape(r.name) << "</figcaption></figure>\n";
        if (!r.errorImage.empty())
            out << "<figure><img src=\"" << escape(r.errorImage) << "\" alt=\"error of " << escape(r.name)
                << "\"/><figcaption>relative squared error, " << escape(r.name) << "</figcaption></figure>\n";
    }
    out << "</body>\n</html>\n";
    if (!out) fail("cannot write {}", file.string());
}

} // namespace effigi::app
