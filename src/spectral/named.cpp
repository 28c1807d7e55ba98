// Named spectra (effigi/spectral/named.hpp): data/spectra/<name>.csv, installed to
// <data directory>/spectra/. Each file is read once, checked strictly (every error names
// the file and line), and kept for the life of the process.
#include "effigi/spectral/named.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/core/module.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

namespace effigi {
namespace {

namespace fs = std::filesystem;

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

bool toFloat(std::string_view s, float& out) {
    s = trim(s);
    double d = 0.0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), d);
    if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return false;
    if (!std::isfinite(d) || std::abs(d) > 3e38) return false;
    out = float(d);
    return true;
}

fs::path spectraDirectory() { return dataDirectory() / "spectra"; }

/// A name is a file stem: letters, digits, '-', '_' and '.', starting with a letter or
/// digit, so that it can never leave the spectra directory.
bool validName(const std::string& name) {
    if (name.empty() || !std::isalnum(static_cast<unsigned char>(name[0]))) return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    });
}

/// '#' comment lines, then the header "lambda,value", then "λ,v" rows with λ in nm,
/// strictly ascending; blank lines are ignored.
Spectrum readSpectrumCsv(const fs::path& path) {
    std::ifstream in(path);
    if (!in) fail("cannot open named spectrum file {}", path.string());
    std::vector<float> lambdas, values;
    bool header = false;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        std::string_view l = trim(line);
        if (l.empty() || l.front() == '#') continue;
        SourceLocation where{path.string(), n};
        if (!header) {
            if (l != "lambda,value") failAt(where, "expected the header 'lambda,value', got '{}'", excerpt(l));
            header = true;
            continue;
        }
        std::size_t comma = l.find(',');
        float lambda = 0.f, value = 0.f;
        if (comma == l.npos || !toFloat(l.substr(0, comma), lambda) || !toFloat(l.substr(comma + 1), value))
            failAt(where, "expected 'wavelength,value' (two finite numbers), got '{}'", excerpt(l));
        if (!(lambda > 0.f)) failAt(where, "wavelength {} nm is not positive", lambda);
        if (!lambdas.empty() && !(lambda > lambdas.back()))
            failAt(where, "wavelengths must be strictly ascending: {} nm follows {} nm", lambda, lambdas.back());
        lambdas.push_back(lambda);
        values.push_back(value);
    }
    if (!header) fail("{}: no 'lambda,value' header", path.string());
    if (lambdas.empty()) fail("{}: holds no data", path.string());
    return Spectrum::piecewiseLinear(std::move(lambdas), std::move(values));
}

struct Cache {
    std::mutex mutex;
    std::map<std::string, Spectrum> spectra;
};

Cache& cache() {
    static Cache c;
    return c;
}

} // namespace

std::vector<std::string> namedSpectrumNames() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(spectraDirectory(), ec)) {
        const fs::path& p = entry.path();
        if (p.extension() == ".csv" && entry.is_regular_file(ec)) names.push_back(p.stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

Spectrum namedSpectrum(const std::string& name) {
    Cache& c = cache();
    std::lock_guard<std::mutex> lock(c.mutex);
    if (auto it = c.spectra.find(name); it != c.spectra.end()) return it->second;

    if (!validName(name)) fail("'{}' is not a spectrum name (letters, digits, '-', '_', '.')", excerpt(name));
    fs::path path = spectraDirectory() / (name + ".csv");
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        std::vector<std::string> names = namedSpectrumNames();
        if (names.empty())
            fail("unknown named spectrum '{}': no spectra in {} (is EFFIGI_DATA_DIR right?)", name,
                 spectraDirectory().string());
        std::string hint = didYouMean(name, names);
        if (!hint.empty()) fail("unknown named spectrum '{}' (did you mean '{}'?)", name, hint);
        fail("unknown named spectrum '{}' (known: {})", name, fmt::join(names, ", "));
    }
    Spectrum s = readSpectrumCsv(path);
    c.spectra.emplace(name, s);
    return s;
}

} // namespace effigi
