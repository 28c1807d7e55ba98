#pragma once
// The check library behind effigi-conform. A *suite* checks every component of one tag
// (bsdf, warp, sampler, ...); the *session* instantiates each component the registry
// knows in each conformance configuration its schema declares and hands it to the suite
// of its tag as a *target*; the suite records one *row* per check.
//
// Statistical checks record a p-value; their verdicts are decided together at the end
// with Šidák's correction, so that the chance of any false failure in a whole run is the
// stated significance level (0.01). Deterministic checks decide on the spot.
//
// Adding a suite for a new tag is one file, conformance/<tag>_suite.cpp, ending in
//   EFFIGI_CONFORMANCE_SUITE("tag", "what it checks", runFunction);
#include "effigi/core/registry.hpp"
#include "effigi/math/rng.hpp"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace effigi::conform {

enum class Verdict { Pass, Fail, Skip, Info };

/// Ends the name of each configuration added at a range end: "alpha = 4 (range end)".
inline constexpr std::string_view RangeEndSuffix = " (range end)";

const char* verdictName(Verdict v);

/// Observed and expected counts of a chi-square test over a grid of nx × ny cells
/// (row-major, row 0 = lowest y), kept so that a failing test can be drawn.
struct Histogram {
    int nx = 0, ny = 0;
    std::string xLabel, yLabel;  // e.g. "φ", "cos θ"
    std::vector<double> observed, expected;
    /// Samples outside the grid (absorbed, delta lobes, outside the domain).
    double outsideObserved = 0.0, outsideExpected = 0.0;
};

/// One line of the report: a component × configuration × check.
struct Row {
    std::string tag, component, config, check;
    Verdict verdict = Verdict::Pass;
    std::string figure;            ///< the number behind the verdict (p-value, max albedo, ...)
    std::optional<double> pValue;  ///< statistical checks; verdict set by Session::finish
    std::string detail;            ///< what was measured or what went wrong
    std::vector<std::string> files;          ///< images written for this row
    std::shared_ptr<Histogram> histogram;    ///< chi-square checks
    double seconds = 0.0;
};

using ParamList = std::vector<std::pair<std::string, PropertyValue>>;

struct Options {
    std::string tag;        ///< only this tag ("" = every tag with a suite)
    std::string component;  ///< only components of this name ("" = all)
    std::uint64_t seed = 0x5eed2026;
    bool quick = false;     ///< smaller sample counts and fewer angles
    double alpha = 0.01;    ///< family-wise significance of the whole run
    std::filesystem::path outDir = "conform-out";  ///< images of failing chi-square tests
    int threads = 0;        ///< 0 = oneTBB's default
};

/// One component × configuration under test, as handed to a suite.
class Target {
public:
    Target(Registry& reg, const Options& opts, std::string tag, std::string component, ConformanceConfig config,
           Ref<IComponent> object);

    const std::string& tag() const { return m_tag; }
    const std::string& component() const { return m_component; }
    const std::string& config() const { return m_config.name; }
    const ConformanceConfig& configuration() const { return m_config; }
    Ref<IComponent> object() const { return m_object; }
    template <typename I> Ref<I> as() const { return effigi::query<I>(m_object); }
    Registry& registry() const { return m_registry; }

    /// A fresh instance of the component with this configuration's parameters, the
    /// overrides replacing or adding parameters (e.g. a sampler's sample_count).
    Ref<IComponent> create(const ParamList& overrides = {}) const;
    /// Whether the component's schema declares a parameter.
    bool hasParameter(const std::string& name) const;

    bool quick() const { return m_options.quick; }
    /// A configuration the session added at a parameter's range end (RangeEnds::Probed).
    bool rangeEnd() const { return m_config.name.ends_with(RangeEndSuffix); }
    std::uint64_t seed() const { return m_options.seed; }
    /// `full` normally, `quick` under --quick.
    std::uint64_t count(std::uint64_t full, std::uint64_t quick) const { return m_options.quick ? quick : full; }
    /// A generator for one check, seeded by the run's seed and the target's and check's
    /// names only: a check draws the same numbers whatever else runs.
    PCG32 rng(std::string_view key) const;
    /// A 64-bit seed derived the same way (for components that take a seed).
    std::uint64_t derivedSeed(std::string_view key) const;

    // ---- results -------------------------------------------------------------------
    /// A deterministic check: passes iff ok.
    Row& expect(const std::string& check, bool ok, std::string figure, std::string detail = {});
    /// A statistical test; the verdict (p >= Šidák-corrected level) is decided at the end.
    Row& test(const std::string& check, double pValue, std::string figure, std::string detail = {},
              std::shared_ptr<Histogram> histogram = {});
    Row& skip(const std::string& check, std::string reason);
    Row& info(const std::string& check, std::string figure, std::string detail = {});
    std::vector<Row>& rows() { return m_rows; }

private:
    Row& add(const std::string& check, Verdict v, std::string figure, std::string detail);

    Registry& m_registry;
    const Options& m_options;
    std::string m_tag, m_component;
    ConformanceConfig m_config;
    Ref<IComponent> m_object;
    std::vector<Row> m_rows;
    double m_lastTime;
};

/// A deterministic check over many probes: how many were bad, the first bad one
/// described, and (where the check has a tolerance) the largest error over it.
struct Tally {
    std::uint64_t checked = 0, bad = 0;
    double worst = 0.0;  ///< largest error / tolerance seen, where the check records it
    std::string first;
    void note(bool ok, const std::string& what) {
        ++checked;
        if (!ok && bad++ == 0) first = what;
    }
    std::string figure() const { return std::to_string(bad) + " bad of " + std::to_string(checked); }
    std::string detail(const std::string& good) const { return bad ? "first: " + first : good; }
};

// ---- suites --------------------------------------------------------------------------

using SuiteFunction = void (*)(Target&);

/// Whether the session adds, to each component's conformance configurations, one per end
/// of every ranged float parameter (float, texture, spectrum) that has a default and that
/// no configuration sets to that end: "alpha = 4" alone, the others at their defaults.
enum class RangeEnds { Configured, Probed };

struct Suite {
    std::string tag;
    std::string summary;  ///< one line: what the suite checks
    SuiteFunction run = nullptr;
    RangeEnds rangeEnds = RangeEnds::Configured;
};

/// Every suite linked into the program, sorted by tag.
std::vector<Suite> suites();
const Suite* findSuite(const std::string& tag);

struct SuiteRegistration {
    SuiteRegistration(std::string tag, std::string summary, SuiteFunction run,
                      RangeEnds rangeEnds = RangeEnds::Configured);
};

/// The configurations a suite probing range ends adds to `configs` for `schema`.
std::vector<ConformanceConfig> rangeEndConfigs(const Schema& schema, const std::vector<ConformanceConfig>& configs);

#define EFFIGI_CONFORMANCE_CONCAT2(a, b) a##b
#define EFFIGI_CONFORMANCE_CONCAT(a, b) EFFIGI_CONFORMANCE_CONCAT2(a, b)
/// Registers a suite from its own file: EFFIGI_CONFORMANCE_SUITE("bsdf", "...", runBsdf),
/// optionally followed by RangeEnds::Probed.
#define EFFIGI_CONFORMANCE_SUITE(tag, summary, ...)                                             \
    static const ::effigi::conform::SuiteRegistration EFFIGI_CONFORMANCE_CONCAT(effigiSuite_, __LINE__){ \
        tag, summary, __VA_ARGS__}

/// The smallest relative error ε of a density, on a region holding a fraction q of the
/// samples, that a chi-square test of n samples in `cells` cells at level alphaSingle
/// catches with probability 0.9 (power.cpp).
double detectableDensityError(double n, double cells, double alphaSingle, double q);

// ---- session -------------------------------------------------------------------------

/// A component in one configuration: the unit of work.
struct Job {
    std::string tag, component;
    ConformanceConfig config;
};

class Session {
public:
    explicit Session(Options options, Registry& registry = Registry::instance());

    const Options& options() const { return m_options; }

    /// The (tag, component, configuration) jobs the options select, in report order.
    /// A schema without conformance configurations gets one, "default".
    std::vector<Job> plan() const;
    /// Run every planned job (in parallel, results in plan order), then finish().
    void run(const std::function<void(const Job&)>& started = {});
    /// Run one job now (tests); call finish() after the last.
    void runJob(const Job& job);
    /// Decide the statistical verdicts with Šidák's correction over every test run and
    /// write the images of failing chi-square tests into options().outDir.
    void finish();

    const std::vector<Row>& rows() const { return m_rows; }
    /// Number of statistical tests (rows with a p-value).
    int statisticalTests() const;
    /// Per-test level: 1 − (1 − α)^(1/m).
    double alphaSingle() const;
    int count(Verdict v) const;
    /// Rows of a given check name (tests).
    std::vector<const Row*> find(const std::string& component, const std::string& checkPrefix) const;

    /// The smallest defects the run's statistical tests catch with probability 0.9 at its
    /// settings, one line each (power.cpp); printed after the table.
    std::vector<std::string> powerLines() const;

    void printTable(std::FILE* out) const;
    void writeJson(std::FILE* out) const;
    void writeHtml(const std::filesystem::path& file) const;

private:
    std::vector<Row> runJobRows(const Job& job);

    Options m_options;
    Registry& m_registry;
    std::vector<Row> m_rows;
    double m_wallSeconds = 0.0;
};

} // namespace effigi::conform
