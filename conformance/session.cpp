// The conformance session: which components run in which configurations, running them
// in parallel, and deciding the statistical verdicts with Šidák's correction.
#include "conformance/conformance.hpp"
#include "conformance/histogram.hpp"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>

namespace effigi::conform {

namespace {

double now() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}


std::map<std::string, Suite>& suiteTable() {
    static std::map<std::string, Suite> table;
    return table;
}

/// A file name from a row's names: ASCII letters, digits, '-', '_' and '.'; θ becomes
/// "theta", other non-ASCII characters and '=' vanish, anything else becomes '_'.
std::string safeName(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        if (s.compare(i, 2, "θ") == 0) {
            out += "theta";
            ++i;
        } else if (c >= 0x80 || c == '=') {
            continue;
        } else if (std::isalnum(c) || c == '-' || c == '_' || c == '.') {
            out += char(c);
        } else if (out.empty() || out.back() != '_') {
            out += '_';
        }
    }
    return out;
}

} // namespace

const char* verdictName(Verdict v) {
    switch (v) {
    case Verdict::Pass: return "PASS";
    case Verdict::Fail: return "FAIL";
    case Verdict::Skip: return "SKIP";
    case Verdict::Info: return "INFO";
    }
    return "?";
}

// ---- suites --------------------------------------------------------------------------

SuiteRegistration::SuiteRegistration(std::string tag, std::string summary, SuiteFunction run, RangeEnds rangeEnds) {
    suiteTable()[tag] = Suite{tag, std::move(summary), run, rangeEnds};
}

std::vector<ConformanceConfig> rangeEndConfigs(const Schema& schema, const std::vector<ConformanceConfig>& configs) {
    auto named = [&](const std::string& param, double v) {
        for (const ConformanceConfig& c : configs)
            for (const auto& [k, value] : c.params)
                if (k == param && std::holds_alternative<double>(value) && std::get<double>(value) == v) return true;
        return false;
    };
    std::vector<ConformanceConfig> out;
    // Each end is set on the configuration with the fewest parameters (usually "default"):
    // it holds what the component needs (a nested BSDF, a file) and little else.
    ConformanceConfig base{"default", {}};
    if (!configs.empty())
        base = *std::min_element(configs.begin(), configs.end(),
                                 [](const auto& a, const auto& b) { return a.params.size() < b.params.size(); });
    for (const ParamSpec& p : schema.params()) {
        bool number = p.type == ParamType::Float || p.type == ParamType::Texture || p.type == ParamType::Spectrum;
        // Parameters without a default only make sense together with others (alpha_u
        // with alpha_v): a configuration of their own would be a usage error.
        if (!number || !p.defaultValue || p.ignored) continue;
        for (const std::optional<double>& end : {p.min, p.max})
            if (end && std::isfinite(*end) && !named(p.name, *end)) {
                ConformanceConfig c{fmt::format("{} = {:g}{}", p.name, *end, RangeEndSuffix), base.params};
                std::erase_if(c.params, [&](const auto& kv) { return kv.first == p.name; });
                c.params.emplace_back(p.name, PropertyValue(*end));
                out.push_back(std::move(c));
            }
    }
    return out;
}

std::vector<Suite> suites() {
    std::vector<Suite> out;
    for (const auto& [tag, s] : suiteTable()) out.push_back(s);
    return out;
}

const Suite* findSuite(const std::string& tag) {
    auto it = suiteTable().find(tag);
    return it == suiteTable().end() ? nullptr : &it->second;
}

// ---- target --------------------------------------------------------------------------

Target::Target(Registry& reg, const Options& opts, std::string tag, std::string component, ConformanceConfig config,
               Ref<IComponent> object)
    : m_registry(reg), m_options(opts), m_tag(std::move(tag)), m_component(std::move(component)),
      m_config(std::move(config)), m_object(std::move(object)), m_lastTime(now()) {}

Ref<IComponent> Target::create(const ParamList& overrides) const {
    Properties p(m_tag, m_component);
    for (const auto& [name, value] : m_config.params)
        if (std::none_of(overrides.begin(), overrides.end(), [&](const auto& o) { return o.first == name; }))
            p.set(name, value);
    for (const auto& [name, value] : overrides) p.set(name, value);
    return m_registry.create(m_tag, m_component, p);
}

bool Target::hasParameter(const std::string& name) const {
    return m_registry.info(m_tag, m_component).schema.find(name) != nullptr;
}

std::uint64_t Target::derivedSeed(std::string_view key) const {
    std::string full = m_tag + "/" + m_component + "/" + m_config.name + "/" + std::string(key);
    return mixBits(m_options.seed ^ mixBits(fnv1a(full)));
}

PCG32 Target::rng(std::string_view key) const {
    std::uint64_t s = derivedSeed(key);
    return PCG32(s, mixBits(s + 1));
}

Row& Target::add(const std::string& check, Verdict v, std::string figure, std::string detail) {
    Row r;
    r.tag = m_tag;
    r.component = m_component;
    r.config = m_config.name;
    r.check = check;
    r.verdict = v;
    r.figure = std::move(figure);
    r.detail = std::move(detail);
    double t = now();
    r.seconds = t - m_lastTime;
    m_lastTime = t;
    m_rows.push_back(std::move(r));
    return m_rows.back();
}

Row& Target::expect(const std::string& check, bool ok, std::string figure, std::string detail) {
    return add(check, ok ? Verdict::Pass : Verdict::Fail, std::move(figure), std::move(detail));
}

Row& Target::test(const std::string& check, double pValue, std::string figure, std::string detail,
                  std::shared_ptr<Histogram> histogram) {
    // A NaN p-value (a broken statistic) counts as a failure, never as a pass.
    Row& r = add(check, Verdict::Pass, std::move(figure), std::move(detail));
    r.pValue = std::isnan(pValue) ? 0.0 : std::clamp(pValue, 0.0, 1.0);
    r.histogram = std::move(histogram);
    return r;
}

Row& Target::skip(const std::string& check, std::string reason) { return add(check, Verdict::Skip, "-", std::move(reason)); }

Row& Target::info(const std::string& check, std::string figure, std::string detail) {
    return add(check, Verdict::Info, std::move(figure), std::move(detail));
}

// ---- session -------------------------------------------------------------------------

Session::Session(Options options, Registry& registry) : m_options(std::move(options)), m_registry(registry) {}

std::vector<Job> Session::plan() const {
    std::vector<Job> jobs;
    for (const auto& [tag, name] : m_registry.list()) {
        if (!findSuite(tag)) continue;
        if (!m_options.tag.empty() && m_options.tag != tag) continue;
        if (!m_options.component.empty() && m_options.component != name) continue;
        std::vector<ConformanceConfig> configs;
        try {
            configs = m_registry.info(tag, name).schema.conformance();
        } catch (const std::exception&) {
            // A module that fails to load is reported by runJob as a failing row.
        }
        if (configs.empty()) configs.push_back({"default", {}});
        if (findSuite(tag)->rangeEnds == RangeEnds::Probed) {
            try {
                for (auto& c : rangeEndConfigs(m_registry.info(tag, name).schema, configs)) configs.push_back(std::move(c));
            } catch (const std::exception&) {
            }
        }
        for (auto& c : configs) jobs.push_back({tag, name, std::move(c)});
    }
    return jobs;
}

std::vector<Row> Session::runJobRows(const Job& job) {
    const Suite* suite = findSuite(job.tag);
    Target target(m_registry, m_options, job.tag, job.component, job.config, nullptr);
    if (!suite) {
        target.skip("suite", "no conformance suite for tag '" + job.tag + "'");
        return std::move(target.rows());
    }
    Ref<IComponent> object;
    try {
        object = target.create();
    } catch (const std::exception& e) {
        target.expect("instantiate", false, "error", e.what());
        return std::move(target.rows());
    }
    Target t(m_registry, m_options, job.tag, job.component, job.config, object);
    try {
        suite->run(t);
    } catch (const std::exception& e) {
        t.expect("exception", false, "error", e.what());
    }
    return std::move(t.rows());
}

void Session::runJob(const Job& job) {
    std::vector<Row> rows = runJobRows(job);
    m_rows.insert(m_rows.end(), std::make_move_iterator(rows.begin()), std::make_move_iterator(rows.end()));
}

void Session::run(const std::function<void(const Job&)>& started) {
    double t0 = now();
    std::vector<Job> jobs = plan();
    // Load every module first: dlopen from many threads at once gains nothing.
    for (const Job& j : jobs) {
        try {
            m_registry.info(j.tag, j.component);
        } catch (const std::exception&) {
        }
    }
    std::vector<std::vector<Row>> results(jobs.size());
    std::mutex progressMutex;
    auto body = [&](std::size_t i) {
        if (started) {
            std::lock_guard lock(progressMutex);
            started(jobs[i]);
        }
        results[i] = runJobRows(jobs[i]);
    };
    std::unique_ptr<tbb::global_control> limit;
    if (m_options.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(m_options.threads));
    tbb::parallel_for(std::size_t(0), jobs.size(), body);
    for (auto& r : results) m_rows.insert(m_rows.end(), std::make_move_iterator(r.begin()), std::make_move_iterator(r.end()));
    finish();
    m_wallSeconds = now() - t0;
}

int Session::statisticalTests() const {
    return int(std::count_if(m_rows.begin(), m_rows.end(), [](const Row& r) { return r.pValue.has_value(); }));
}

double Session::alphaSingle() const {
    int m = std::max(1, statisticalTests());
    // Šidák: m independent tests at level a each fail at least once with probability
    // 1 − (1 − a)^m; solving for the family-wise level α gives a. Written with log1p and
    // expm1 so that tiny levels keep their digits.
    return -std::expm1(std::log1p(-m_options.alpha) / double(m));
}

void Session::finish() {
    const double a = alphaSingle();
    for (Row& r : m_rows) {
        if (!r.pValue) continue;
        r.verdict = *r.pValue >= a ? Verdict::Pass : Verdict::Fail;
        if (r.verdict == Verdict::Fail && r.histogram && r.files.empty()) {
            std::string stem = safeName(r.tag + "-" + r.component + "-" + r.config + "-" + r.check);
            try {
                r.files = writeHistogramImages(*r.histogram, m_options.outDir / stem);
            } catch (const std::exception& e) {
                r.detail += std::string(r.detail.empty() ? "" : "; ") + "could not write images: " + e.what();
            }
        }
    }
}

int Session::count(Verdict v) const {
    return int(std::count_if(m_rows.begin(), m_rows.end(), [v](const Row& r) { return r.verdict == v; }));
}

std::vector<const Row*> Session::find(const std::string& component, const std::string& checkPrefix) const {
    std::vector<const Row*> out;
    for (const Row& r : m_rows)
        if (r.component == component && r.check.rfind(checkPrefix, 0) == 0) out.push_back(&r);
    return out;
}

} // namespace effigi::conform
