#pragma once
// Helpers of the radiosity tests (test_formfactor, test_radiosity*): small scenes of
// rectangles built through the registry, a mesh and an accelerator over them, form
// factors between whole shapes, and the closed forms of Howell's catalogue.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iformfactor.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/imesh.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/isolver.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace effigi::test {

inline Ref<IComponent> create(const std::string& tag, const std::string& name, Properties p) {
    return Registry::instance().create(tag, name, p);
}
/// A constant spectrum value.
inline SpectrumValue constant(float v) {
    SpectrumValue s;
    s.values = {v};
    return s;
}

inline Ref<IComponent> create(const std::string& tag, const std::string& name) {
    return create(tag, name, Properties(tag, name));
}

/// A diffuse shape ("rectangle" or "cube") of reflectance rho, emitting radiance le if
/// le > 0 (constant spectra), placed by toWorld.
inline Ref<IShape> diffuseShape(const std::string& type, const Transform& toWorld, float rho, float le = 0.f,
                                bool flip = false) {
    Properties b("bsdf", "diffuse");
    b.set("reflectance", constant(rho));
    Properties p("shape", type);
    p.set("to_world", toWorld);
    p.set("bsdf", ComponentValue{"bsdf", create("bsdf", "diffuse", b)});
    if (flip) p.set("flip_normals", true);
    if (le > 0.f) {
        Properties e("emitter", "area");
        e.set("radiance", constant(le));
        p.set("emitter", ComponentValue{"emitter", create("emitter", "area", e)});
    }
    Ref<IShape> s = query<IShape>(create("shape", type, p));
    REQUIRE(s);
    return s;
}

/// A unit square (side 1) from the [-1,1]² rectangle: scale 0.5, then `place`.
inline Ref<IShape> unitSquare(const Transform& place, float rho = 0.5f, float le = 0.f) {
    return diffuseShape("rectangle", place * Transform::scale({0.5f, 0.5f, 1.f}), rho, le);
}

/// Shapes with a mesh and an accelerator over them: what form factors need.
struct Rig {
    std::vector<Ref<IShape>> shapes;
    std::vector<const IShape*> ptrs;
    Ref<IMesh> mesh;
    Ref<IIntersect> accel;
    FormFactorContext ctx;

    Rig(std::vector<Ref<IShape>> s, float maxEdge, int bins = 4) : shapes(std::move(s)) {
        for (auto& x : shapes) ptrs.push_back(x.get());
        Properties mp("mesh", "uniform");
        mp.set("max_edge", double(maxEdge));
        mp.set("bins", std::int64_t(bins));
        mesh = query<IMesh>(create("mesh", "uniform", mp));
        REQUIRE(mesh);
        mesh->build(ptrs);
        accel = query<IIntersect>(create("accelerator", "embree"));
        REQUIRE(accel);
        accel->build(ptrs);
        ctx.mesh = mesh.get();
        ctx.shapes = ptrs;
        ctx.visibility = accel.get();
    }

    /// Elements of shape s.
    std::vector<std::uint32_t> elementsOf(std::uint32_t s) const {
        std::vector<std::uint32_t> out;
        for (std::uint32_t i = 0; i < mesh->elementCount(); ++i)
            if (mesh->elements()[i].shape == s) out.push_back(i);
        return out;
    }
    double areaOf(std::uint32_t s) const {
        double a = 0.0;
        for (std::uint32_t i : elementsOf(s)) a += mesh->elements()[i].area;
        return a;
    }
    /// Shape-to-shape form factor F_PQ = Σ_{i∈P} A_i Σ_{j∈Q} F_ij / A_P, from rows.
    double shapeFormFactor(const IFormFactor& ff, std::uint32_t p, std::uint32_t q) const {
        std::vector<float> row(mesh->elementCount());
        double sum = 0.0;
        for (std::uint32_t i : elementsOf(p)) {
            ff.row(i, row);
            double s = 0.0;
            for (std::uint32_t j : elementsOf(q)) s += row[j];
            sum += mesh->elements()[i].area * s;
        }
        return sum / areaOf(p);
    }
};

/// A render or solve without a progress bar.
inline RenderControl quiet() {
    RenderControl c;
    c.progress = false;
    return c;
}

/// Form-factor parameters: the component's name and (name, value) pairs.
inline Properties formFactorParams(const std::string& name, std::vector<std::pair<std::string, PropertyValue>> values) {
    Properties p("formfactor", name);
    for (auto& [k, v] : values) p.set(k, v);
    return p;
}

inline Ref<IFormFactor> makeFormFactor(const std::string& name, Properties p, const FormFactorContext& ctx) {
    Ref<IFormFactor> ff = query<IFormFactor>(create("formfactor", name, p));
    REQUIRE(ff);
    ff->prepare(ctx);
    return ff;
}

inline Ref<ISolver> makeSolver(const std::string& name, std::int64_t maxIterations, double tolerance) {
    Properties p("solver", name);
    p.set("max_iterations", maxIterations);
    p.set("tolerance", tolerance);
    Ref<ISolver> s = query<ISolver>(create("solver", name, p));
    REQUIRE(s);
    return s;
}

/// Howell's catalogue, C-11: two parallel, directly opposed a × b rectangles at distance c.
inline double howellParallel(double a, double b, double c) {
    double X = a / c, Y = b / c, pi = 3.14159265358979323846;
    double x1 = std::sqrt(1 + X * X), y1 = std::sqrt(1 + Y * Y);
    return 2.0 / (pi * X * Y) *
           (0.5 * std::log((1 + X * X) * (1 + Y * Y) / (1 + X * X + Y * Y)) + X * y1 * std::atan(X / y1) +
            Y * x1 * std::atan(Y / x1) - X * std::atan(X) - Y * std::atan(Y));
}

/// Howell's catalogue, C-14: rectangles of width w (from) and height h (to) sharing an
/// edge of length l at 90°.
inline double howellPerpendicular(double w, double h, double l) {
    double W = w / l, H = h / l, pi = 3.14159265358979323846, W2 = W * W, H2 = H * H;
    double logTerm = std::log((1 + W2) * (1 + H2) / (1 + W2 + H2)) +
                     W2 * std::log(W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2))) +
                     H2 * std::log(H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2)));
    return (W * std::atan(1 / W) + H * std::atan(1 / H) - std::sqrt(H2 + W2) * std::atan(1 / std::sqrt(H2 + W2)) +
            0.25 * logTerm) /
           (pi * W);
}

} // namespace effigi::test
