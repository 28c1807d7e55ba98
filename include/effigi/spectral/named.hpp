#pragma once
// Spectra shipped with effigi, by name: data/spectra/<name>.csv (one spectrum per file,
// '#' lines naming the published source, then "lambda,value" rows in nm), copied to
// share/effigi/spectra/ at build time. Scenes use them as
// <spectrum name="reflectance" value="macbeth-13"/>; components (conductor IORs) by code.
#include "effigi/spectral/spectrum.hpp"

#include <string>
#include <vector>

namespace effigi {

/// The named spectrum (loaded once, then cached); throws effigi::Error naming the
/// closest known names when there is none.
Spectrum namedSpectrum(const std::string& name);
/// Every name available, sorted.
std::vector<std::string> namedSpectrumNames();

} // namespace effigi
