// Error against run time: effigi converge's CSV, plot and report, its convergence rate
// on a scene with an analytic answer, and noise-target rendering.
#include "app_runner.hpp"

#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>
#include <pugixml.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

const std::string Plane = EFFIGI_SOURCE_DIR "/tests/data/converge/plane.xml";

/// The analytic image of tests/data/converge/plane.xml: 0.5 everywhere.
fs::path writeConstantReference(const fs::path& dir, int res) {
    fs::path p = dir / "reference.exr";
    std::vector<float> px(std::size_t(res) * res * 3, 0.5f);
    auto out = OIIO::ImageOutput::create(p.string());
    OIIO::ImageSpec spec(res, res, 3, OIIO::TypeDesc::FLOAT);
    REQUIRE(out);
    REQUIRE(out->open(p.string(), spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    REQUIRE(out->close());
    return p;
}

using Row = std::map<std::string, std::string>;

std::vector<Row> readCSV(const fs::path& p, std::vector<std::string>& header) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    std::stringstream hs(line);
    for (std::string h; std::getline(hs, h, ',');) header.push_back(h);
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        Row r;
        std::string cell;
        for (const auto& h : header) {
            std::getline(ss, cell, ',');
            r[h] = cell;
        }
        rows.push_back(r);
    }
    return rows;
}

/// Least-squares slope of log y against log x.
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = double(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        double a = std::log(x[i]), b = std::log(y[i]);
        sx += a, sy += b, sxx += a * a, sxy += a * b;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace

TEST_CASE("converge: CSV columns, monotone time, plot and a self-contained report", "[converge]") {
    fs::path dir = tempDir("converge");
    fs::path ref = writeConstantReference(dir, 32);
    AppResult r = runApp("converge " + Plane + " -D res=32 --reference " + ref.string() +
                         " --variant \"deep: max_depth=3\" --variant \"direct: max_depth=2\" --spp 16 --no-progress --out " +
                         (dir / "out").string());
    INFO(r.out);
    REQUIRE(r.exitCode == 0);

    std::vector<std::string> header;
    auto rows = readCSV(dir / "out/convergence.csv", header);
    CHECK(header == std::vector<std::string>{"configuration", "spp", "samples", "seconds", "rmse", "relmse", "mae",
                                             "nan_fraction", "estimated_relmse"});
    std::map<std::string, std::vector<Row>> byConfig;
    for (const auto& row : rows) byConfig[row.at("configuration")].push_back(row);
    REQUIRE(byConfig.size() == 2);
    for (const auto& [name, cps] : byConfig) {
        INFO(name);
        REQUIRE(cps.size() == 5);  // checkpoints at 1, 2, 4, 8, 16 spp
        for (std::size_t i = 0; i < cps.size(); ++i) {
            CHECK(std::stoull(cps[i].at("spp")) == (1ull << i));
            CHECK(std::stoull(cps[i].at("samples")) == (1ull << i) * 32 * 32);
            CHECK(std::stod(cps[i].at("nan_fraction")) == 0.0);
            if (i > 0) CHECK(std::stod(cps[i].at("seconds")) > std::stod(cps[i - 1].at("seconds")));
        }
        CHECK(std::stod(cps.back().at("relmse")) < std::stod(cps.front().at("relmse")));
    }

    // The report parses as XML (polyglot HTML5) and refers only to files beside it.
    pugi::xml_document doc;
    pugi::xml_parse_result parsed = doc.load_file((dir / "out/report.html").c_str());
    INFO(parsed.description());
    REQUIRE(parsed);
    int images = 0;
    for (pugi::xpath_node n : doc.select_nodes("//*[@src or @href]")) {
        std::string target = n.node().attribute("src") ? n.node().attribute("src").value() : n.node().attribute("href").value();
        INFO(target);
        CHECK(target.find(':') == std::string::npos);  // no scheme: no network
        CHECK(target.find('/') == std::string::npos);  // beside the report
        CHECK(fs::exists(dir / "out" / target));
        ++images;
    }
    CHECK(images == 4);  // final image and error image of each configuration
    CHECK(doc.select_node("//*[local-name()='svg']//*[local-name()='polyline']"));
    fs::remove_all(dir);
}

TEST_CASE("converge: the path tracer's RMSE falls as samples^-1/2 on an analytic scene, times increase",
          "[converge]") {
    fs::path dir = tempDir("converge-rate");
    fs::path ref = writeConstantReference(dir, 64);
    // The rate is fitted against the sample count, not the seconds: wall time on a loaded
    // machine is not proportional to the work (a timed assertion would be flaky).
    AppResult r = runApp("converge " + Plane + " --reference " + ref.string() + " --spp 512 -t 1 --no-progress --out " +
                         (dir / "out").string());
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    std::vector<std::string> header;
    auto rows = readCSV(dir / "out/convergence.csv", header);
    std::vector<double> spp, rmse;
    double lastSeconds = 0.0;
    for (const auto& row : rows) {
        double seconds = std::stod(row.at("seconds"));
        CHECK(seconds > lastSeconds);  // the error-vs-time axis: every checkpoint later than the one before
        lastSeconds = seconds;
        if (std::stoull(row.at("spp")) >= 16) {  // passes of >= 64k samples
            spp.push_back(std::stod(row.at("spp")));
            rmse.push_back(std::stod(row.at("rmse")));
        }
    }
    REQUIRE(spp.size() == 6);  // 16 ... 512 spp
    double slope = logLogSlope(spp, rmse);
    INFO("fitted slope of log RMSE against log samples: " << slope);
    CHECK(slope == Approx(-0.5).margin(0.1));

    // The renderer's own estimate is calibrated against the true error (box filter: the
    // per-pixel estimate is the film pixel's): within a factor 1.5 at the last checkpoint.
    double measured = std::stod(rows.back().at("relmse")), estimated = std::stod(rows.back().at("estimated_relmse"));
    INFO("estimated " << estimated << ", measured " << measured);
    CHECK(estimated / measured == Approx(1.0).margin(0.5));
    fs::remove_all(dir);
}

TEST_CASE("render: --target-relmse stops at the noise target", "[converge]") {
    fs::path dir = tempDir("target");
    AppResult r = runApp("render " + Plane + " --target-relmse 2e-4 --no-progress -o " + (dir / "t.exr").string());
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    CHECK(r.out.find("reached after") != std::string::npos);
    // The image really is that accurate: measured relMSE against the analytic 0.5,
    // within a factor 2 of the target (the estimate's calibration above).
    auto in = OIIO::ImageInput::open((dir / "t.exr").string());
    REQUIRE(in);
    const auto& spec = in->spec();
    std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    double rel = 0.0;
    for (int i = 0; i < spec.width * spec.height; ++i)
        for (int c = 0; c < 3; ++c) {
            double d = px[std::size_t(i) * spec.nchannels + c] - 0.5;
            rel += d * d / (0.25 + 0.01);
        }
    rel /= 3.0 * spec.width * spec.height;
    CHECK(rel < 4e-4);
    CHECK(std::string(spec.get_string_attribute("effigi/spp")) != "16");  // it did not stop at the scene's spp
    fs::remove_all(dir);
}

TEST_CASE("render: --time renders progressively and marks references", "[converge]") {
    fs::path dir = tempDir("time");
    AppResult r = runApp("render " + Plane + " --time 0.5 --reference --no-progress -o " + (dir / "r.exr").string());
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    auto in = OIIO::ImageInput::open((dir / "r.exr").string());
    REQUIRE(in);
    CHECK(std::string(in->spec().get_string_attribute("effigi/reference")) == "true");
    CHECK(std::stoull(std::string(in->spec().get_string_attribute("effigi/spp"))) >= 1);
    fs::remove_all(dir);
}

TEST_CASE("converge: another renderer keeps the parameters of the scene's that it shares", "[converge]") {
    // max_depth 1 shows emitters only: the plane is black, relMSE against 0.5 is ~0.96.
    // A renderer that lost the scene's max_depth (ptracer at its default, unbounded) would
    // render the lit plane, relMSE ~0.
    fs::path dir = tempDir("converge-keep");
    fs::path ref = writeConstantReference(dir, 16);
    AppResult r = runApp("converge " + Plane + " -D res=16 -D max_depth=1 --reference " + ref.string() +
                         " --renderer path,ptracer --spp 4 --no-progress --out " + (dir / "out").string());
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    std::vector<std::string> header;
    std::map<std::string, double> last;
    for (const auto& row : readCSV(dir / "out/convergence.csv", header)) last[row.at("configuration")] = std::stod(row.at("relmse"));
    REQUIRE(last.size() == 2);
    CHECK(last.at("path") > 0.9);
    CHECK(last.at("ptracer") > 0.9);
    fs::remove_all(dir);
}
