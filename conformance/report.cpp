// The session's reports: the terminal table, JSON and a self-contained HTML page.
#include "conformance/conformance.hpp"

#include <fmt/format.h>

#include <fstream>

namespace effigi::conform {

namespace {

/// Display width of UTF-8 text (code points; every character used here is one column).
std::size_t width(const std::string& s) {
    std::size_t n = 0;
    for (unsigned char c : s)
        if ((c & 0xC0) != 0x80) ++n;
    return n;
}

std::string pad(const std::string& s, std::size_t w) { return s + std::string(w > width(s) ? w - width(s) : 0, ' '); }

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        default:
            if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", int(c));
            else out += c;
        }
    }
    return out + "\"";
}

std::string html(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '&': out += "&amp;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

std::string pText(const Row& r) {
    if (!r.pValue) return "";
    return fmt::format("{:.3g}", *r.pValue);
}

} // namespace

void Session::printTable(std::FILE* out) const {
    std::size_t wName = 9, wConfig = 6, wCheck = 5, wFigure = 6;
    for (const Row& r : m_rows) {
        wName = std::max(wName, width(r.tag + "/" + r.component));
        wConfig = std::max(wConfig, width(r.config));
        wCheck = std::max(wCheck, width(r.check));
        wFigure = std::max(wFigure, width(r.figure));
    }
    std::fprintf(out, "%s  %s  %s  %s  %s  %s\n", pad("verdict", 7).c_str(), pad("component", wName).c_str(),
                 pad("config", wConfig).c_str(), pad("check", wCheck).c_str(), pad("figure", wFigure).c_str(),
                 "p-value");
    for (const Row& r : m_rows) {
        std::fprintf(out, "%s  %s  %s  %s  %s  %s\n", pad(verdictName(r.verdict), 7).c_str(),
                     pad(r.tag + "/" + r.component, wName).c_str(), pad(r.config, wConfig).c_str(),
                     pad(r.check, wCheck).c_str(), pad(r.figure, wFigure).c_str(), pText(r).c_str());
        if (r.verdict == Verdict::Fail || r.verdict == Verdict::Skip) {
            if (!r.detail.empty()) std::fprintf(out, "         %s\n", r.detail.c_str());
            for (const auto& f : r.files) std::fprintf(out, "         image: %s\n", f.c_str());
        }
    }
    std::fprintf(out,
                 "\n%zu checks: %d passed, %d failed, %d skipped, %d info. %d statistical tests at family-wise "
                 "α = %g (Šidák: p >= %.3g each).%s\n",
                 m_rows.size(), count(Verdict::Pass), count(Verdict::Fail), count(Verdict::Skip), count(Verdict::Info),
                 statisticalTests(), m_options.alpha, alphaSingle(),
                 m_wallSeconds > 0.0 ? fmt::format(" {:.1f} s.", m_wallSeconds).c_str() : "");
    for (const std::string& line : powerLines()) std::fprintf(out, "%s\n", line.c_str());
}

void Session::writeJson(std::FILE* out) const {
    std::string s = "{\n";
    s += fmt::format("  \"seed\": {},\n  \"quick\": {},\n  \"alpha\": {},\n  \"alpha_single\": {:.6g},\n"
                     "  \"statistical_tests\": {},\n  \"passed\": {},\n  \"failed\": {},\n  \"skipped\": {},\n"
                     "  \"seconds\": {:.3f},\n",
                     m_options.seed, m_options.quick, m_options.alpha, alphaSingle(), statisticalTests(),
                     count(Verdict::Pass), count(Verdict::Fail), count(Verdict::Skip), m_wallSeconds);
    std::vector<std::string> power = powerLines();
    s += "  \"power\": [";
    for (std::size_t i = 0; i < power.size(); ++i) s += (i ? ", " : "") + jsonString(power[i]);
    s += "],\n  \"rows\": [\n";
    for (std::size_t i = 0; i < m_rows.size(); ++i) {
        const Row& r = m_rows[i];
        std::string files;
        for (std::size_t k = 0; k < r.files.size(); ++k) files += (k ? ", " : "") + jsonString(r.files[k]);
        s += fmt::format("    {{\"tag\": {}, \"component\": {}, \"config\": {}, \"check\": {}, \"verdict\": {}, "
                         "\"figure\": {}, \"p_value\": {}, \"detail\": {}, \"files\": [{}], \"seconds\": {:.4f}}}{}\n",
                         jsonString(r.tag), jsonString(r.component), jsonString(r.config), jsonString(r.check),
                         jsonString(verdictName(r.verdict)), jsonString(r.figure),
                         r.pValue ? fmt::format("{:.6g}", *r.pValue) : "null", jsonString(r.detail), files, r.seconds,
                         i + 1 < m_rows.size() ? "," : "");
    }
    s += "  ]\n}\n";
    std::fputs(s.c_str(), out);
}

void Session::writeHtml(const std::filesystem::path& file) const {
    if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file);
    if (!out) fail("cannot write {}", file.string());
    const std::filesystem::path base = std::filesystem::absolute(file).parent_path();
    out << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>effigi-conform report</title>\n"
           "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
           "td,th{padding:2px 8px;border-bottom:1px solid #ddd;text-align:left;vertical-align:top}"
           ".PASS{color:#176917}.FAIL{color:#b00;font-weight:bold}.SKIP{color:#876500}.INFO{color:#555}"
           "img{image-rendering:pixelated;max-width:420px;margin:4px}.d{color:#555;font-size:90%}</style>"
           "</head><body>\n<h1>effigi-conform</h1>\n";
    out << fmt::format("<p>{} checks: {} passed, {} failed, {} skipped. {} statistical tests at family-wise "
                       "&alpha; = {} (&Scaron;id&aacute;k: p &ge; {:.3g} each). Seed {}{}.</p>\n",
                       m_rows.size(), count(Verdict::Pass), count(Verdict::Fail), count(Verdict::Skip),
                       statisticalTests(), m_options.alpha, alphaSingle(), m_options.seed,
                       m_options.quick ? ", --quick" : "");
    for (const std::string& line : powerLines()) out << "<p class=\"d\">" << html(line) << "</p>\n";
    out << "<table><tr><th>verdict</th><th>component</th><th>config</th><th>check</th><th>figure</th>"
           "<th>p-value</th><th>detail</th></tr>\n";
    for (const Row& r : m_rows) {
        out << fmt::format("<tr><td class=\"{0}\">{0}</td><td>{1}/{2}</td><td>{3}</td><td>{4}</td><td>{5}</td>"
                           "<td>{6}</td><td class=\"d\">{7}",
                           verdictName(r.verdict), html(r.tag), html(r.component), html(r.config), html(r.check),
                           html(r.figure), pText(r), html(r.detail));
        for (const auto& f : r.files) {
            std::filesystem::path rel = std::filesystem::relative(std::filesystem::absolute(f), base);
            out << fmt::format("<br><a href=\"{0}\"><img src=\"{0}\" alt=\"{0}\"></a>", html(rel.string()));
        }
        out << "</td></tr>\n";
    }
    out << "</table>\n</body></html>\n";
}

} // namespace effigi::conform
