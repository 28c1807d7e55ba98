// effigi.Scene (py_scene.hpp). Images reach NumPy without a copy: the film's developed
// pixels (one std::vector) are converted in place and handed over with a capsule that
// frees them when the array dies.
#include "py_scene.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/progressive.hpp"
#include "effigi/xml/loader.hpp"

#include <fmt/ranges.h>
#include <pybind11/numpy.h>

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <functional>

namespace effigi::python {

namespace {

/// The camera's film node, inline or by <ref>; a camera without one gets the hdrfilm it
/// would get by default, declared, so that it can be configured like a declared one.
xml::Node* cameraFilm(xml::Node& root) {
    xml::Node* camera = nullptr;
    for (xml::Child& c : root.children)
        if (c.node && c.node->tag == "camera") camera = c.node.get();
    if (!camera) return nullptr;  // the loader reports it
    std::function<xml::Node*(xml::Node&, const std::string&)> byId = [&](xml::Node& n, const std::string& id) {
        if (n.id == id) return &n;
        for (xml::Child& c : n.children)
            if (c.node)
                if (xml::Node* f = byId(*c.node, id)) return f;
        return static_cast<xml::Node*>(nullptr);
    };
    for (xml::Child& c : camera->children) {
        if (c.node && c.node->tag == "film") return c.node.get();
        if (!c.node)
            if (xml::Node* f = byId(root, c.refId); f && f->tag == "film") return f;
    }
    auto film = std::make_unique<xml::Node>();
    film->tag = "film", film->type = "hdrfilm", film->where = camera->where;
    film->props = Properties("film", "hdrfilm", camera->where);
    xml::Child child;
    child.node = std::move(film);
    child.where = camera->where;
    camera->children.push_back(std::move(child));
    return camera->children.back().node.get();
}

void override(xml::Node& film, const std::string& name, PropertyValue value) {
    SourceLocation where = film.props.has(name) ? film.props.whereOf(name) : film.where;
    film.props.remove(name);
    film.props.set(name, std::move(value), where);
}

/// XYZ instead of RGB from hdrfilm (converted here to any space, exactly as the film
/// would: the same float matrix on the same floats), and the spectral bins asked for.
/// Returns the film's colour space, the default space of render().
std::string prepareFilm(xml::Node& root, std::optional<int> spectralBins) {
    xml::Node* film = cameraFilm(root);
    if (!film) return "srgb";
    if (spectralBins && film->type != "hdrfilm")
        failAt(film->where, "film '{}' records no spectral bins (hdrfilm does)", film->type);
    if (film->type != "hdrfilm") return "srgb";
    const std::string space = film->props.has("colorspace") ? film->props.getString("colorspace") : "srgb";
    override(*film, "pixel_format", std::string("xyz"));
    if (spectralBins) override(*film, "spectral_bins", std::int64_t(*spectralBins));
    return space;
}

/// Removes a temporary directory however the spectral read ends.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        std::string pattern = (std::filesystem::temp_directory_path() / "effigi-py-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) fail("cannot create a temporary directory in {}", pattern);
        path = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

} // namespace

py::object handOver(std::vector<float>&& pixels, int height, int width, int channels, int used) {
    auto* owned = new std::vector<float>(std::move(pixels));
    py::capsule free(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
    const auto f = py::ssize_t(sizeof(float));
    // Explicit strides (pybind11 2.10 would compute them from NumPy 1's descriptor layout).
    return py::array(py::dtype::of<float>(), {py::ssize_t(height), py::ssize_t(width), py::ssize_t(used)},
                     {f * width * channels, f * channels, f}, owned->data(), free);
}

PyScene::PyScene(std::unique_ptr<xml::Node> root, std::optional<int> spectralBins) {
    m_colorSpace = prepareFilm(*root, spectralBins);
    m_scene = loadScene(*root);
}

PyScene PyScene::fromFile(const std::string& path, const std::map<std::string, std::string>& defines,
                          std::optional<int> spectralBins) {
    xml::ParseOptions opt{defines};
    py::gil_scoped_release release;  // meshes and textures may take a while
    PyScene s(xml::parseFile(path, opt), spectralBins);
    s.m_source = path;
    return s;
}

PyScene PyScene::fromString(const std::string& xml, const std::map<std::string, std::string>& defines,
                            std::optional<int> spectralBins) {
    xml::ParseOptions opt{defines};
    py::gil_scoped_release release;
    PyScene s(xml::parseString(xml, "<string>", opt), spectralBins);
    s.m_source = "<string>";
    return s;
}

py::object PyScene::render(std::optional<std::uint64_t> spp, std::uint64_t seed, int threads,
                           const std::optional<std::string>& space, bool spectral, bool progress) {
    // Every argument is checked before the render, not after it.
    if (spp && *spp == 0) fail("render: spp must be at least 1");
    if (threads < 0) fail("render: threads must be 0 (all cores) or more, got {}", threads);
    const RGBColorSpace* target = outputSpace(space.value_or(m_colorSpace));
    if (spectral && spectralBins() == 0)
        fail("render: the film of {} records no spectral bins: set spectral_bins on the film, or load the scene "
             "with spectral_bins=N", m_source);
    RenderControl control;
    control.seed = seed;
    control.threads = threads;
    control.progress = progress;
    // Ctrl-C between passes of a progressive render: Python's handler only sets a flag,
    // looked at here; the KeyboardInterrupt is raised once the render has stopped.
    PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
    Image colour;
    spectral_exr::SpectralImage bins;
    {
        // One render of a scene at a time (its film is shared). The lock is taken without
        // the GIL, so a thread waiting for it never blocks the pass callback's acquire.
        py::gil_scoped_release release;
        std::lock_guard lock(*m_rendering);
        if (spp) {
            ProgressiveOptions prog;
            prog.spp = *spp;
            prog.progress = progress;
            m_stats = renderProgressive(*m_scene, control, prog, [&](const PassReport&) {
                py::gil_scoped_acquire acquire;
                if (PyErr_CheckSignals() == 0) return true;
                PyErr_Fetch(&type, &value, &trace);
                return false;
            });
        } else {
            m_stats = m_scene->renderer().render(*m_scene, control);
        }
        if (!type && spectral) bins = developSpectral();
        else if (!type) colour = developColour(target);
    }
    if (type) {
        m_stats->interrupted = true;
        PyErr_Restore(type, value, trace);
        throw py::error_already_set();
    }
    if (!spectral) return handOver(std::move(colour.pixels), colour.height, colour.width, colour.channels(), 3);
    const int nb = int(bins.bands());
    py::array lambda(py::dtype::of<double>(), {py::ssize_t(nb)}, {py::ssize_t(sizeof(double))}, bins.centers.data());
    return py::make_tuple(handOver(std::move(bins.values), bins.height, bins.width, nb, nb), lambda);
}

const RGBColorSpace* PyScene::outputSpace(const std::string& name) {
    if (name == "xyz") return nullptr;
    if (name == "srgb-linear" || name == "linear-srgb" || name == "rec709") return &RGBColorSpace::get(ColorSpaceId::SRGB);
    if (auto id = RGBColorSpace::parse(name)) return &RGBColorSpace::get(*id);
    fail("render: space '{}' is not one of srgb-linear (srgb), rec2020, acescg, xyz", name);
}

Image PyScene::developColour(const RGBColorSpace* target) const {
    Image img = m_scene->camera().film().develop();
    const int n = img.channels();
    auto named = [&](const char* a, const char* b, const char* c) {
        return n >= 3 && img.channelNames[0] == a && img.channelNames[1] == b && img.channelNames[2] == c;
    };
    const RGBColorSpace* source = nullptr;  // null: the film gave XYZ
    if (named("R", "G", "B")) source = &RGBColorSpace::get(RGBColorSpace::parse(m_colorSpace).value());
    else if (!named("X", "Y", "Z"))
        fail("render: renderer '{}' puts no colour on the film (its channels: {})", rendererName(),
             fmt::join(img.channelNames, ", "));
    if (source == target) return img;
    const std::size_t pixels = std::size_t(img.width) * std::size_t(img.height);
    for (std::size_t i = 0; i < pixels; ++i) {
        float* p = img.pixels.data() + i * std::size_t(n);
        Vector3f v(p[0], p[1], p[2]);
        if (source) v = source->toXYZ(v);
        if (target) v = target->fromXYZ(v);
        // As the film does: no Inf or NaN in an image (a huge value stays huge).
        for (int c = 0; c < 3; ++c) p[c] = std::isnan(v[c]) ? 0.f : std::clamp(v[c], -FLT_MAX, FLT_MAX);
    }
    return img;
}

spectral_exr::SpectralImage PyScene::developSpectral() const {
    // IFilm develops only the colour image; the bins come through hdrfilm's spectral EXR
    // (float32, so exact), written to a temporary directory and read back.
    TempDir dir;
    std::filesystem::path spectral;
    for (const auto& f : m_scene->camera().film().write(dir.path / "film.exr", {}))
        if (f.string().ends_with(".spectral.exr")) spectral = f;
    if (spectral.empty()) fail("render: renderer '{}' put no spectral bins on the film (path does)", rendererName());
    return spectral_exr::readFile(spectral);
}

py::tuple PyScene::size() const {
    Vector2i s = m_scene->camera().film().size();
    return py::make_tuple(s.x, s.y);
}

int PyScene::spectralBins() const { return m_scene->camera().film().spectralBins(); }

py::dict PyScene::stats() const {
    py::dict d;
    if (!m_stats) return d;
    d["samples"] = m_stats->samples;
    d["rejected_samples"] = m_stats->rejectedSamples;
    d["seconds"] = m_stats->seconds;
    d["interrupted"] = m_stats->interrupted;
    return d;
}

std::string PyScene::repr() const {
    Vector2i s = m_scene->camera().film().size();
    return fmt::format("<effigi.Scene {}: {}x{}, {} shapes, {} emitters, {}>", m_source, s.x, s.y,
                       m_scene->shapes().size(), m_scene->emitters().size(), rendererName());
}

} // namespace effigi::python
