#pragma once
// The outputs of `effigi converge`: convergence.csv, convergence.svg (log-log error
// against time, one line per configuration, fitted slope in the legend) and report.html
// (plot, final images, false-colour error images), all in one directory and referring
// only to files beside them.
#include <filesystem>
#include <string>
#include <vector>

namespace effigi::app {

struct Checkpoint {
    std::uint64_t spp = 0, samples = 0;
    double seconds = 0.0;
    double rmse = -1.0, relMSE = -1.0, mae = -1.0;  // < 0: no reference
    double nanFraction = 0.0;
    double estimatedRelMSE = -1.0;                  // < 0: the renderer keeps no estimate
};

struct ConfigurationRun {
    std::string name;
    std::vector<Checkpoint> checkpoints;
    std::string image, errorImage;  // file names in the output directory ("" if none)
};

/// Least-squares slope of log(error) against log(seconds) over the checkpoints with at
/// least `minSpp` samples per pixel; `useEstimate` fits the renderer's own estimate.
double fittedSlope(const std::vector<Checkpoint>& cps, bool useEstimate, std::uint64_t minSpp = 4);

void writeCSV(const std::filesystem::path& file, const std::vector<ConfigurationRun>& runs);
/// Plots relMSE (or, without a reference, the estimated relMSE) against time.
std::string plotSVG(const std::vector<ConfigurationRun>& runs, bool haveReference);
void writeHTML(const std::filesystem::path& file, const std::string& sceneName, const std::vector<ConfigurationRun>& runs,
               bool haveReference, const std::string& svg);

} // namespace effigi::app
