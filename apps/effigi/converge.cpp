// effigi converge: render configurations of one scene progressively, measure error
// against time at checkpoints 1, 2, 4, ... spp, and write convergence.csv, a log-log
// plot and an HTML report. Configurations are the product of --renderer choices and
// --variant parameter sets, all measured in one run on one machine.
#include "commands.hpp"
#include "converge_report.hpp"
#include "image_io.hpp"
#include "output_check.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/image_metrics.hpp"
#include "effigi/render/progressive.hpp"
#include "effigi/xml/loader.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace effigi::app {

namespace {

struct Variant {
    std::string name;
    std::map<std::string, std::string> defines;
};

/// "label: k=v k=v" (or just "k=v k=v", labelled by its text).
Variant parseVariant(const std::string& text) {
    Variant v;
    std::string body = text;
    if (auto colon = text.find(':'); colon != std::string::npos && text.find('=') > colon) {
        v.name = text.substr(0, colon);
        body = text.substr(colon + 1);
    }
    std::istringstream ss(body);
    std::string kv;
    while (ss >> kv) {
        auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0) fail("--variant: expected name=value, got '{}'", kv);
        v.defines[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    if (v.defines.empty()) fail("--variant '{}' sets nothing", text);
    if (v.name.empty()) v.name = body;
    return v;
}

/// Make the scene use renderer `type`: keep its parameters if it already is one, else
/// those of the scene's renderer that `type` also has (max_depth, rr_depth,
/// hide_emitters, ...), so that every configuration renders the same light transport as
/// the scene and its reference.
void overrideRenderer(xml::Node& root, const std::string& type) {
    for (auto& child : root.children) {
        if (!child.node || child.node->tag != "renderer") continue;
        if (child.node->type != type) {
            xml::Node& n = *child.node;
            Properties kept("renderer", type, n.where);
            Registry& reg = Registry::instance();
            if (reg.knows("renderer", type)) {
                const Schema& schema = reg.info("renderer", type).schema;
                for (const Properties::Entry& e : n.props.entries())
                    if (!e.fromDefault && schema.find(e.name)) kept.set(e.name, e.value, e.where);
            }
            n.type = type;
            n.props = std::move(kept);
            n.children.clear();
        }
        return;
    }
    auto node = std::make_unique<xml::Node>();
    node->tag = "renderer";
    node->type = type;
    node->where = root.where;
    node->props = Properties("renderer", type, root.where);
    root.children.push_back(xml::Child{"", std::move(node), "", root.where});
}

std::string fileSafe(const std::string& s) {
    std::string r;
    for (char c : s) r += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
    return r;
}

std::vector<float> firstThreeChannels(const Image& img) {
    std::vector<float> rgb(std::size_t(img.width) * img.height * 3);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(std::size_t(y) * img.width + x) * 3 + c] = c < img.channels() ? img.at(x, y, c) : 0.f;
    return rgb;
}

} // namespace

int converge(const std::vector<std::string>& args) {
    std::string scenePath, referencePath, outDir = "converge-out";
    std::vector<std::string> renderers;
    std::vector<Variant> variants;
    std::map<std::string, std::string> defines;
    ProgressiveOptions prog;
    RenderControl control;
    auto value = [&](std::size_t& i) {
        if (i + 1 >= args.size()) fail("option {} needs a value", args[i]);
        return args[++i];
    };
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--reference") referencePath = value(i);
        else if (a == "--renderer") {
            std::istringstream ss(value(i));
            for (std::string r; std::getline(ss, r, ',');)
                if (!r.empty()) renderers.push_back(r);
        } else if (a == "--variant") variants.push_back(parseVariant(value(i)));
        else if (a == "-D") {
            std::string kv = value(i);
            auto eq = kv.find('=');
            if (eq == std::string::npos || eq == 0) fail("-D expects name=value, got '{}'", kv);
            defines[kv.substr(0, eq)] = kv.substr(eq + 1);
        } else if (a == "--time") prog.timeBudget = std::stod(value(i));
        else if (a == "--spp") prog.spp = std::stoull(value(i));
        else if (a == "--out") outDir = value(i);
        else if (a == "-t") control.threads = std::stoi(value(i));
        else if (a == "--seed") control.seed = std::stoull(value(i));
        else if (a == "--no-progress") control.progress = false;
        else if (!a.empty() && a[0] == '-') fail("converge: unknown option '{}'", a);
        else if (scenePath.empty()) scenePath = a;
        else fail("converge: more than one scene given");
    }
    if (scenePath.empty()) fail("converge: no scene file given");
    if (prog.timeBudget <= 0.0 && prog.spp == 0) prog.timeBudget = 10.0;
    prog.progress = control.progress;

    bool haveReference = !referencePath.empty();
    Image reference;
    if (haveReference) reference = readRGB(referencePath);
    // Every file goes into outDir, after all the rendering: probe it first (creates it).
    requireWritable(std::filesystem::path(outDir) / "convergence.csv");

    if (renderers.empty()) renderers.push_back("");
    if (variants.empty()) variants.push_back({"", {}});
    std::vector<ConfigurationRun> runs;
    for (const auto& r : renderers)
        for (const auto& v : variants) {
            ConfigurationRun run;
            run.name = r.empty() ? (v.name.empty() ? "scene" : v.name) : (v.name.empty() ? r : r + " " + v.name);
            xml::ParseOptions opt;
            opt.defines = defines;
            for (const auto& [k, val] : v.defines) opt.defines[k] = val;
            auto root = xml::parseFile(scenePath, opt);
            if (!r.empty()) overrideRenderer(*root, r);
            auto scene = loadScene(*root);
            IFilm& film = scene->camera().film();
            std::fprintf(stderr, "configuration %s\n", run.name.c_str());
            renderProgressive(*scene, control, prog, [&](const PassReport& p) {
                Checkpoint c;
                c.spp = p.spp;
                c.samples = p.stats.samples;
                c.seconds = p.seconds;
                c.nanFraction = p.stats.samples ? double(p.stats.rejectedSamples) / double(p.stats.samples) : 0.0;
                c.estimatedRelMSE = p.estimatedRelMSE;
                if (haveReference) {
                    ErrorMetrics m = compareImages(film.develop(), reference);
                    c.rmse = m.rmse, c.relMSE = m.relMSE, c.mae = m.mae;
                }
                run.checkpoints.push_back(c);
                return !control.stopRequested();
            });
            Image img = film.develop();
            run.image = fileSafe(run.name) + ".png";
            writePNG(std::filesystem::path(outDir) / run.image, img.width, img.height, firstThreeChannels(img));
            if (haveReference) {
                std::vector<float> err = relativeSquaredError(img, reference);
                // Colour scale: ten times the image's mean relative error saturates.
                double mean = 0.0;
                for (float e : err) mean += e;
                mean /= double(std::max<std::size_t>(err.size(), 1));
                run.errorImage = fileSafe(run.name) + "-error.png";
                writePNG(std::filesystem::path(outDir) / run.errorImage, img.width, img.height,
                         falseColour(err, float(10.0 * mean)));
            }
            runs.push_back(std::move(run));
        }

    std::filesystem::path out(outDir);
    writeCSV(out / "convergence.csv", runs);
    std::string svg = plotSVG(runs, haveReference);
    {
        std::ofstream f(out / "convergence.svg");
        f << svg;
        if (!f) fail("cannot write {}", (out / "convergence.svg").string());
    }
    writeHTML(out / "report.html", std::filesystem::path(scenePath).filename().string(), runs, haveReference, svg);

    std::printf("%-28s %8s %9s %12s %12s %10s\n", "configuration", "spp", "seconds", "relMSE", "est. relMSE", "slope");
    for (const auto& r : runs) {
        if (r.checkpoints.empty()) continue;
        const Checkpoint& c = r.checkpoints.back();
        std::printf("%-28s %8llu %9.2f %12.4g %12.4g %10.2f\n", r.name.c_str(), (unsigned long long)c.spp, c.seconds,
                    c.relMSE, c.estimatedRelMSE, fittedSlope(r.checkpoints, !haveReference));
        if (haveReference && c.relMSE > 0.0 && c.estimatedRelMSE > 0.0)
            std::printf("  %s: estimated / measured relMSE = %.2f\n", r.name.c_str(), c.estimatedRelMSE / c.relMSE);
    }
    std::printf("wrote %s, %s, %s\n", (out / "convergence.csv").c_str(), (out / "convergence.svg").c_str(),
                (out / "report.html").c_str());
    return 0;
}

} // namespace effigi::app
