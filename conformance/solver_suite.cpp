// Solver suite: an ISolver, in each of its configurations, solves small radiosity systems
// whose exact solution is known by Gaussian elimination (solveDirect) and is checked for
// what ISolver promises:
//  - finite, non-negative radiosity, whatever happened;
//  - an honest error bound: the true relative error Σ A|B − B*| / Σ A B* never exceeds
//    the reported errorBound (converged or stopped at max_iterations);
//  - a claim of convergence only with errorBound ≤ tolerance (or, where no bound exists,
//    the residual ≤ tolerance);
//  - a truthful report: iterations within max_iterations, a history, the solver named.
// Rooms: a closed cube of reflectance 0.99 emitting everywhere (B = E/(1 − ρ)); a stiff
// closed box (ρ from 0.5 to 0.999, one end emitting); the same box open at one end with
// white walls (ρ = 1: only a computed contraction factor gives a bound); and a room that
// emits nothing (B = 0 exactly). Form factors: `analytic` without visibility, so every
// room is exact up to float storage. All checks are deterministic.
#include "conformance/conformance.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/iformfactor.hpp"
#include "effigi/interfaces/imesh.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/isolver.hpp"
#include "effigi/render/radiosity_solver.hpp"

#include <fmt/format.h>

#include <cmath>

namespace effigi::conform {

namespace {

/// B is stored as float: the stored values differ from the solver's by ≤ 2⁻²⁴ relative.
constexpr double FloatStorage = 1e-7;

struct Room {
    std::string name;
    std::vector<Ref<IShape>> shapes;
};

SpectrumValue constant(float v) {
    SpectrumValue s;
    s.values = {v};
    return s;
}

Ref<IShape> surface(Registry& reg, const std::string& type, const Transform& toWorld, float rho, float le) {
    Properties b("bsdf", "diffuse");
    b.set("reflectance", constant(rho));
    Properties p("shape", type);
    p.set("to_world", toWorld);
    p.set("bsdf", ComponentValue{"bsdf", reg.create("bsdf", "diffuse", b)});
    if (type == "cube") p.set("flip_normals", true);
    if (le > 0.f) {
        Properties e("emitter", "area");
        e.set("radiance", constant(le));
        p.set("emitter", ComponentValue{"emitter", reg.create("emitter", "area", e)});
    }
    return query<IShape>(reg.create("shape", type, p));
}

/// The inside of [-1,1]² × [-2,2], faces −z, +z, −x, +x, −y, +y of reflectance rho[f],
/// face 0 emitting radiance le, face `open` (if ≥ 0) left out.
Room box(Registry& reg, std::string name, const float (&rho)[6], float le, int open) {
    const Transform t[6] = {Transform::translate({0, 0, -1}),
                            Transform::translate({0, 0, 1}) * Transform::scale({1.f, -1.f, -1.f}),
                            Transform::translate({-1, 0, 0}) * Transform::rotate({0, 1, 0}, 90.f),
                            Transform::translate({1, 0, 0}) * Transform::rotate({0, 1, 0}, -90.f),
                            Transform::translate({0, -1, 0}) * Transform::rotate({1, 0, 0}, -90.f),
                            Transform::translate({0, 1, 0}) * Transform::rotate({1, 0, 0}, 90.f)};
    Room r{std::move(name), {}};
    for (int f = 0; f < 6; ++f)
        if (f != open)
            r.shapes.push_back(
                surface(reg, "rectangle", Transform::scale({1.f, 1.f, 2.f}) * t[f], rho[f], f == 0 ? le : 0.f));
    return r;
}

std::vector<Room> rooms(Registry& reg) {
    const float stiff[6] = {0.5f, 0.999f, 0.99f, 0.9f, 0.995f, 0.98f}, white[6] = {1, 1, 1, 1, 1, 1};
    std::vector<Room> out;
    out.push_back({"closed cube, ρ = 0.99", {surface(reg, "cube", Transform(), 0.99f, 1.f)}});
    out.push_back(box(reg, "stiff closed box", stiff, 1.f, -1));
    out.push_back(box(reg, "open white box", white, 1.f, 1));
    out.push_back(box(reg, "dark box", stiff, 0.f, -1));
    return out;
}

void runSolverSuite(Target& t) {
    Ref<ISolver> solver = t.as<ISolver>();
    if (!solver) {
        t.expect("interface", false, "-", "component does not implement ISolver");
        return;
    }
    Registry& reg = t.registry();
    RenderControl quiet;
    quiet.progress = false;
    for (const Room& room : rooms(reg)) {
        std::vector<const IShape*> shapes;
        for (const auto& s : room.shapes) shapes.push_back(s.get());
        Properties mp("mesh", "uniform");
        mp.set("max_edge", 1.0);
        mp.set("bins", std::int64_t(4));
        Ref<IMesh> mesh = query<IMesh>(reg.create("mesh", "uniform", mp));
        mesh->build(shapes);
        Properties fp("formfactor", "analytic");
        fp.set("visibility_samples", std::int64_t(0));
        Ref<IFormFactor> ff = query<IFormFactor>(reg.create("formfactor", "analytic", fp));
        FormFactorContext ctx;
        ctx.mesh = mesh.get();
        ctx.shapes = shapes;
        ff->prepare(ctx);
        std::vector<double> exact;
        {
            RadiositySystem sys(*mesh);
            FormFactorMatrix F(*ff, sys.n, quiet, "reference");
            exact = solveDirect(sys, F);
        }

        SolverReport r = solver->solve(*mesh, *ff, quiet);
        const std::string& at = room.name;
        std::size_t bad = 0;
        for (float b : mesh->radiosity())
            if (!(std::isfinite(b) && b >= 0.f)) ++bad;
        t.expect("finite " + at, bad == 0, fmt::format("{} bad of {}", bad, mesh->radiosity().size()),
                 "radiosity finite and non-negative");
        double truth = relativeError(*mesh, exact);
        t.expect("honest bound " + at, truth <= r.errorBound + FloatStorage,
                 fmt::format("error {:.3g} ≤ bound {:.3g}", truth, r.errorBound), r.summary());
        bool claim = !r.converged || (std::isfinite(r.errorBound) ? r.errorBound : r.residual) <= r.tolerance;
        t.expect("converged claim " + at, claim,
                 fmt::format("bound {:.3g}, tolerance {:.3g}", r.errorBound, r.tolerance), r.summary());
        bool report = r.iterations <= r.maxIterations && !r.history.empty() &&
                      r.summary().find(t.component()) != std::string::npos && !(r.converged && r.interrupted);
        t.expect("report " + at, report, fmt::format("{} of {} iterations", r.iterations, r.maxIterations),
                 r.summary());
        t.info("iterations " + at, fmt::format("{}", r.iterations), r.summary());
    }
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("solver",
                         "finite radiosity, an honest error bound against an exact solve, truthful convergence reports",
                         effigi::conform::runSolverSuite);
