// effigi-conform's checks can fail: deliberately wrong components defined here (an
// energy-gaining diffuse, a BSDF whose pdf disagrees with its sampling, a warp whose pdf
// is off by a factor, an integrator whose error bar is too small, samplers that break
// their promises) are each reported as failing by the right check, while the shipped
// components and correct test components pass. Also the runner's command line.
//
// Every session is seeded (the runner's default seed), so these tests are deterministic.
// The wrong components are wrong by large factors: their p-values are below 1e-10 and
// their deterministic figures far outside the tolerances, so the verdicts do not hinge
// on the seed.
#include "conform_session.hpp"
#include "conformance/conformance.hpp"
#include "conformance_helpers.hpp"

#include "app_runner.hpp"

#include <catch2/catch.hpp>

#include <fstream>

using namespace effigi;
using effigi::test::sessionTable;
using effigi::test::verdictOf;
using namespace effigi::conform;
using namespace effigi::conformtest;

namespace {

/// Runs the suites on components named `name` (quick unless told otherwise).
Session runOn(const std::string& tag, const std::string& name, const std::filesystem::path& out, bool quick = true) {
    registerTestComponents();
    Options o;
    o.tag = tag;
    o.component = name;
    o.quick = quick;
    o.outDir = out;
    Session s(o);
    s.run();
    return s;
}

/// The verdicts of every row of a check (prefix match on the check's name).
std::vector<Verdict> verdicts(const Session& s, const std::string& component, const std::string& check) {
    std::vector<Verdict> v;
    for (const Row* r : s.find(component, check)) v.push_back(r->verdict);
    return v;
}

bool allAre(const std::vector<Verdict>& v, Verdict want) {
    return !v.empty() && std::all_of(v.begin(), v.end(), [&](Verdict x) { return x == want; });
}

bool anyIs(const std::vector<Verdict>& v, Verdict want) {
    return std::any_of(v.begin(), v.end(), [&](Verdict x) { return x == want; });
}

} // namespace

TEST_CASE("conformance: shipped components pass their suites", "[conformance]") {
    auto out = test::tempDir("conform-shipped");
    for (auto [tag, name] : {std::pair{"bsdf", "diffuse"}, std::pair{"warp", "cosine_hemisphere"},
                             std::pair{"warp", "ggx_visible_normals"}, std::pair{"sampler", "independent"},
                             std::pair{"function", "spike"}}) {
        Session s = runOn(tag, name, out);
        INFO(sessionTable(s));
        CHECK(s.count(Verdict::Fail) == 0);
        CHECK(s.count(Verdict::Pass) >= 5);
    }
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: an energy-gaining diffuse fails 'energy' only", "[conformance]") {
    auto out = test::tempDir("conform-energy");
    Session s = runOn("bsdf", "test_energy_gain", out);
    INFO(sessionTable(s));
    CHECK(allAre(verdicts(s, "test_energy_gain", "energy"), Verdict::Fail));
    // Its sampling and pdf agree: the distribution checks pass.
    CHECK(allAre(verdicts(s, "test_energy_gain", "chi-square"), Verdict::Pass));
    CHECK(allAre(verdicts(s, "test_energy_gain", "sample weight"), Verdict::Pass));
    CHECK(allAre(verdicts(s, "test_energy_gain", "reciprocity"), Verdict::Pass));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: a BSDF whose pdf disagrees with its sampling fails chi-square, with images", "[conformance]") {
    auto out = test::tempDir("conform-pdf");
    Session s = runOn("bsdf", "test_wrong_pdf", out);
    INFO(sessionTable(s));
    auto chi = s.find("test_wrong_pdf", "chi-square cos θo = 0.6");
    REQUIRE(chi.size() == 1);
    CHECK(chi[0]->verdict == Verdict::Fail);
    CHECK(*chi[0]->pValue < 1e-10);
    // The observed and expected histograms are written and named in the row.
    REQUIRE(chi[0]->files.size() == 2);
    for (const auto& f : chi[0]->files) {
        CHECK(std::filesystem::exists(f));
        CHECK(std::filesystem::file_size(f) > 100);
    }
    // sample() and pdf() report the same (wrong) density, so only the distribution shows it.
    CHECK(allAre(verdicts(s, "test_wrong_pdf", "sample weight"), Verdict::Pass));
    CHECK(allAre(verdicts(s, "test_wrong_pdf", "energy"), Verdict::Pass));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: a BSDF returning a different f from sample() fails 'sample weight'", "[conformance]") {
    auto out = test::tempDir("conform-weight");
    Session s = runOn("bsdf", "test_wrong_weight", out);
    INFO(sessionTable(s));
    CHECK(allAre(verdicts(s, "test_wrong_weight", "sample weight"), Verdict::Fail));
    CHECK(allAre(verdicts(s, "test_wrong_weight", "non-negative"), Verdict::Pass));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: a non-reciprocal BSDF and a leaky mirror are caught", "[conformance]") {
    auto out = test::tempDir("conform-recip");
    Session s = runOn("bsdf", "test_nonreciprocal", out);
    INFO(sessionTable(s));
    CHECK(allAre(verdicts(s, "test_nonreciprocal", "reciprocity"), Verdict::Fail));
    Session m = runOn("bsdf", "test_bad_mirror", out);
    INFO(sessionTable(m));
    CHECK(allAre(verdicts(m, "test_bad_mirror", "delta"), Verdict::Fail));
    CHECK(allAre(verdicts(m, "test_bad_mirror", "stable"), Verdict::Pass));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: a BSDF producing NaN at grazing angles fails 'stable'", "[conformance]") {
    auto out = test::tempDir("conform-nan");
    Session s = runOn("bsdf", "test_grazing_nan", out);
    INFO(sessionTable(s));
    CHECK(allAre(verdicts(s, "test_grazing_nan", "stable"), Verdict::Fail));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: a warp whose pdf is off by a factor fails 'pdf integral' and chi-square", "[conformance]") {
    auto out = test::tempDir("conform-warp");
    Session s = runOn("warp", "test_double_pdf", out);
    INFO(sessionTable(s));
    auto integral = s.find("test_double_pdf", "pdf integral");
    REQUIRE(integral.size() == 1);
    CHECK(integral[0]->verdict == Verdict::Fail);
    CHECK_THAT(integral[0]->figure, Catch::Contains("2.0000"));
    CHECK(allAre(verdicts(s, "test_double_pdf", "chi-square"), Verdict::Fail));
    CHECK(allAre(verdicts(s, "test_double_pdf", "inverse"), Verdict::Pass));
    // A wrong inverse is caught too.
    Session w = runOn("warp", "test_bad_inverse", out);
    INFO(sessionTable(w));
    CHECK(allAre(verdicts(w, "test_bad_inverse", "inverse"), Verdict::Fail));
    CHECK(allAre(verdicts(w, "test_bad_inverse", "chi-square"), Verdict::Pass));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: an integrator whose error bar is too small fails 'error bar'", "[conformance]") {
    auto out = test::tempDir("conform-integrator");
    Session s = runOn("integrator", "test_overconfident", out);
    INFO(sessionTable(s));
    CHECK(allAre(verdicts(s, "test_overconfident", "error bar"), Verdict::Fail));
    // Its estimates are the mean integrator's: unbiased.
    CHECK(allAre(verdicts(s, "test_overconfident", "unbiased"), Verdict::Pass));
    Session b = runOn("integrator", "test_biased", out);
    INFO(sessionTable(b));
    CHECK(anyIs(verdicts(b, "test_biased", "unbiased"), Verdict::Fail));
    Session m = runOn("integrator", "mean", out);
    INFO(sessionTable(m));
    CHECK(m.count(Verdict::Fail) == 0);
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: sampler promises are checked", "[conformance]") {
    auto out = test::tempDir("conform-sampler");
    // A correct jittered sampler passes everything it claims, including N^-1 convergence.
    Session good = runOn("sampler", "test_jittered", out, false);
    INFO(sessionTable(good));
    CHECK(good.count(Verdict::Fail) == 0);
    CHECK(allAre(verdicts(good, "test_jittered", "stratification"), Verdict::Pass));
    // An independent sampler that claims stratification and a faster rate is caught.
    Session liar = runOn("sampler", "test_claims_too_much", out);
    INFO(sessionTable(liar));
    CHECK(allAre(verdicts(liar, "test_claims_too_much", "stratification"), Verdict::Fail));
    CHECK(allAre(verdicts(liar, "test_claims_too_much", "convergence smooth"), Verdict::Fail));
    CHECK(allAre(verdicts(liar, "test_claims_too_much", "uniform"), Verdict::Pass));
    // A sampler whose dimensions are correlated, and one that returns 1.0.
    Session corr = runOn("sampler", "test_correlated", out);
    INFO(sessionTable(corr));
    CHECK(allAre(verdicts(corr, "test_correlated", "independent"), Verdict::Fail));
    CHECK(allAre(verdicts(corr, "test_correlated", "uniform"), Verdict::Pass));
    Session range = runOn("sampler", "test_returns_one", out);
    INFO(sessionTable(range));
    CHECK(allAre(verdicts(range, "test_returns_one", "range"), Verdict::Fail));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: a test integrand with a wrong integral() fails its suite", "[conformance]") {
    auto out = test::tempDir("conform-function");
    Session s = runOn("function", "test_wrong_integral", out);
    INFO(sessionTable(s));
    CHECK(allAre(verdicts(s, "test_wrong_integral", "integral"), Verdict::Fail));
    CHECK(allAre(verdicts(s, "test_wrong_integral", "finite"), Verdict::Pass));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: Šidák level, determinism and reports", "[conformance]") {
    auto out = test::tempDir("conform-report");
    Session a = runOn("warp", "uniform_triangle", out);
    Session b = runOn("warp", "uniform_triangle", out);
    REQUIRE(a.rows().size() == b.rows().size());
    for (std::size_t i = 0; i < a.rows().size(); ++i) CHECK(a.rows()[i].figure == b.rows()[i].figure);
    // m tests at family-wise 0.01: each at 1 − 0.99^(1/m).
    int m = a.statisticalTests();
    REQUIRE(m >= 1);
    CHECK(a.alphaSingle() == Approx(1.0 - std::pow(0.99, 1.0 / m)).epsilon(1e-12));
    auto html = out / "r.html";
    a.writeHtml(html);
    std::ifstream in(html);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK_THAT(text, Catch::Contains("uniform_triangle") && Catch::Contains("PASS"));
    std::filesystem::remove_all(out);
}

TEST_CASE("conformance: effigi-conform command line", "[conformance]") {
    auto out = test::tempDir("conform-cli");
    auto run = [&](const std::string& args) {
        std::string cmd = std::string("EFFIGI_PLUGIN_PATH= ") + EFFIGI_CONFORM_APP + " " + args + " 2>&1";
        test::AppResult r;
        FILE* p = popen(cmd.c_str(), "r");
        REQUIRE(p);
        char buf[4096];
        std::size_t n;
        while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
        int status = pclose(p);
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return r;
    };
    auto ok = run("--quick --tag warp --component uniform_sphere --out " + out.string() + " --json " +
                  (out / "r.json").string() + " --report " + (out / "r.html").string());
    INFO(ok.out);
    CHECK(ok.exitCode == 0);
    CHECK_THAT(ok.out, Catch::Contains("warp/uniform_sphere") && Catch::Contains("chi-square") &&
                           Catch::Contains("Šidák"));
    CHECK(std::filesystem::exists(out / "r.json"));
    CHECK(std::filesystem::exists(out / "r.html"));
    auto list = run("--list --tag bsdf");
    CHECK(list.exitCode == 0);
    CHECK_THAT(list.out, Catch::Contains("bsdf/diffuse") && Catch::Contains("suite warp"));
    CHECK(run("--tag nosuchtag").exitCode == 2);
    CHECK(run("--component nosuchcomponent").exitCode == 2);
    CHECK(run("--seed notanumber").exitCode == 2);
    std::filesystem::remove_all(out);
}
