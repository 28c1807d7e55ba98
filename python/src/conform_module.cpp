// effigi._conform: the conformance suites (libeffigi_conformance, as effigi-conform runs
// them) on the components a tag and a name select, with the report as a dict of the keys
// of `effigi-conform --json`. A module of its own, imported on first use: the check library
// loads OpenImageIO (histograms of failing tests), which `import effigi` should not.
#include "conformance/conformance.hpp"

#include "effigi/core/error.hpp"

#include <pybind11/stl.h>

#include <chrono>

namespace py = pybind11;

namespace {

using namespace effigi::conform;

py::dict rowDict(const Row& r) {
    py::dict d;
    d["tag"] = r.tag;
    d["component"] = r.component;
    d["config"] = r.config;
    d["check"] = r.check;
    d["verdict"] = verdictName(r.verdict);
    d["figure"] = r.figure;
    d["p_value"] = r.pValue ? py::cast(*r.pValue) : py::none();
    d["detail"] = r.detail;
    d["files"] = r.files;
    d["seconds"] = r.seconds;
    return d;
}

py::dict run(const std::string& tag, const std::string& component, bool quick, std::uint64_t seed, int threads,
             const std::string& outDir) {
    if (!tag.empty() && !findSuite(tag)) {
        std::string tags;
        for (const Suite& s : suites()) tags += (tags.empty() ? "" : ", ") + s.tag;
        effigi::fail("no conformance suite for tag '{}' (suites: {})", tag, tags);
    }
    Options opts;
    opts.tag = tag;
    opts.component = component;
    opts.quick = quick;
    opts.seed = seed;
    opts.threads = threads;
    opts.outDir = outDir;
    Session session(opts);
    if (session.plan().empty())
        effigi::fail("no component matches{}{}", tag.empty() ? "" : " tag " + tag,
                     component.empty() ? "" : " component " + component);
    double seconds = 0.0;
    {
        py::gil_scoped_release release;
        const auto t0 = std::chrono::steady_clock::now();
        session.run();
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    py::dict d;
    d["seed"] = opts.seed;
    d["quick"] = opts.quick;
    d["alpha"] = opts.alpha;
    d["alpha_single"] = session.alphaSingle();
    d["statistical_tests"] = session.statisticalTests();
    d["passed"] = session.count(Verdict::Pass);
    d["failed"] = session.count(Verdict::Fail);
    d["skipped"] = session.count(Verdict::Skip);
    d["info"] = session.count(Verdict::Info);
    d["seconds"] = seconds;
    d["power"] = session.powerLines();
    py::list rows;
    for (const Row& r : session.rows()) rows.append(rowDict(r));
    d["rows"] = rows;
    return d;
}

} // namespace

PYBIND11_MODULE(_conform, m) {
    m.doc() = "effigi's conformance suites; use effigi.conform";
    // effigi.Error comes from _effigi, whose translator (global in pybind11) covers this
    // module's effigi::Error too: import it first.
    py::module_::import("effigi._effigi");
    m.def("run", &run, py::arg("tag"), py::arg("component"), py::arg("quick"), py::arg("seed"), py::arg("threads"),
          py::arg("out_dir"));
    m.def("default_seed", [] { return Options{}.seed; });
}
