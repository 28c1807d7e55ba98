// Stiff and extreme radiosity systems: closed enclosures with reflectance up to 0.9999,
// the iteration counts each solver needs, the error bound every solver reports (ISolver)
// checked against the exact solution of the same system, non-convergence reported when
// the limit comes first, near-coincident and touching patches (r → 0), very unequal
// areas. The scaling to 100k elements is measured by bench/radiosity_scale.py, not here.
#include "radiosity_helpers.hpp"

#include "effigi/render/radiosity_solver.hpp"

#include <array>
#include <cmath>
#include <limits>

using namespace effigi;
using namespace effigi::test;

namespace {

/// Area-weighted mean and largest relative error of B against the expected B per element
/// and bin.
std::pair<double, double> errorAgainst(const IMesh& mesh, const std::vector<double>& expected) {
    const int nb = mesh.bins().count();
    double sum = 0.0, area = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < mesh.elementCount(); ++i)
        for (int b = 0; b < nb; ++b) {
            double x = expected[i * nb + b], e = std::abs(mesh.radiosity()[i * nb + b] / x - 1.0);
            sum += mesh.elements()[i].area * x * e;
            area += mesh.elements()[i].area * x;
            worst = std::max(worst, e);
        }
    return {sum / area, worst};
}

std::pair<double, double> errorAgainst(const IMesh& mesh, double expected) {
    return errorAgainst(mesh, std::vector<double>(mesh.radiosity().size(), expected));
}

/// The exact solution of the system the solvers see (float form factors, the mesh's ρ
/// and E), by solveDirect (relative round-off ~1e-16 times the condition number, ≤ 2e4
/// here but for the white room).
std::vector<double> directSolve(const IMesh& mesh, const IFormFactor& ff) {
    RadiositySystem sys(mesh);
    FormFactorMatrix F(ff, sys.n, quiet(), "test");
    return solveDirect(sys, F);
}

/// The measure of ISolver's error bound: Σ A |B − B*| / Σ A B* over elements and bins.
double trueError(const IMesh& mesh, const std::vector<double>& exact) { return relativeError(mesh, exact); }

/// B is stored as float: the stored values differ from the solver's by ≤ 2⁻²⁴ relative.
constexpr double FloatStorage = 1e-7;

/// Smallest and largest row sum of F.
std::pair<double, double> rowSums(const IMesh& mesh, const IFormFactor& ff) {
    std::vector<float> row(mesh.elementCount());
    double lo = 2.0, hi = 0.0;
    for (std::uint32_t i = 0; i < mesh.elementCount(); ++i) {
        ff.row(i, row);
        double s = 0.0;
        for (float f : row) s += f;
        lo = std::min(lo, s), hi = std::max(hi, s);
    }
    return {lo, hi};
}

/// The inside of the box [-1,1]² × [-h,h] as six rectangles facing inwards, reflectance
/// rho[f] per face (−z, +z, −x, +x, −y, +y), face `emitting` with radiance 1; face
/// `open` (if ≥ 0) left out.
std::vector<Ref<IShape>> box(float h, std::array<float, 6> rho, int emitting, int open = -1) {
    Transform t[6] = {Transform::translate({0, 0, -1}),
                      Transform::translate({0, 0, 1}) * Transform::scale({1.f, -1.f, -1.f}),
                      Transform::translate({-1, 0, 0}) * Transform::rotate({0, 1, 0}, 90.f),
                      Transform::translate({1, 0, 0}) * Transform::rotate({0, 1, 0}, -90.f),
                      Transform::translate({0, -1, 0}) * Transform::rotate({1, 0, 0}, -90.f),
                      Transform::translate({0, 1, 0}) * Transform::rotate({1, 0, 0}, 90.f)};
    std::vector<Ref<IShape>> shapes;
    for (int f = 0; f < 6; ++f)
        if (f != open)
            shapes.push_back(diffuseShape("rectangle", Transform::scale({1.f, 1.f, h}) * t[f], rho[f],
                                          f == emitting ? 1.f : 0.f));
    return shapes;
}

std::array<float, 6> uniform(float rho) { return {rho, rho, rho, rho, rho, rho}; }

const std::vector<std::string> AllSolvers = {"jacobi", "gaussseidel", "southwell", "progressive", "gmres"};

} // namespace

TEST_CASE("stiff: closed cube with reflectance 0.9 to 0.9999 gives B = E / (1 − ρ) within the reported bound",
          "[radiosity][stiff]") {
    // The inside of a cube, 2 × 2 elements per face, every element emitting E = π (L = 1)
    // and reflecting ρ. All rows of a closed enclosure sum to 1, so B = E + ρ B and
    // B = E / (1 − ρ) exactly: 10 E … 10⁴ E. Form factors: `analytic` without visibility
    // (a convex enclosure), rows exact to ~1e-7 (float storage); with row sums in
    // [s₋, s₊] the exact B of the system lies in [E/(1 − ρs₋), E/(1 − ρs₊)], a relative
    // deviation δ from E/(1 − ρ) (≤ 1e-3 at ρ = 0.9999) measured from the rows.
    //
    // Every solver stops when its error bound ε (ISolver) is ≤ τ = 1e-4. Checked: ε ≤ τ;
    // the true error against the exact solution of the same system (directSolve) is ≤ ε;
    // the area-weighted error against E/(1 − ρ) is ≤ ε(1 + δ) + δ. Single elements may
    // deviate a little more: ≤ 3τ + δ (by symmetry all elements are alike for Jacobi,
    // Gauss–Seidel and GMRES; relaxation leaves ±1 shot of unevenness). Iterations
    // needed, measured (Jacobi exactly: its bound after k sweeps is ρᵏ⁺¹/(1 − 2ρᵏ⁺¹)):
    //   ρ        jacobi  gaussseidel  southwell  progressive  gmres
    //   0.9          87           48       1074         1062      1
    //   0.99        916          494      11014        11002      1
    //   0.999      9205         4950     110400       110388      1
    //   0.9999    92020        49473         —            —       1
    // GMRES needs one step because the residual of B = E is uniform, an eigenvector of
    // F; the non-uniform rooms below need more. Jacobi and relaxation at 0.9999 (92020
    // sweeps, 10⁶ relaxations) are left out to keep the test fast; "the bound is honest"
    // covers those solvers in stiff rooms.
    struct Expect {
        float rho;
        std::vector<std::pair<std::string, std::uint64_t>> counts;
    };
    for (const Expect& x :
         {Expect{0.9f, {{"jacobi", 87}, {"gaussseidel", 48}, {"southwell", 1074}, {"progressive", 1062}, {"gmres", 1}}},
          Expect{0.99f,
                 {{"jacobi", 916}, {"gaussseidel", 494}, {"southwell", 11014}, {"progressive", 11002}, {"gmres", 1}}},
          Expect{0.999f,
                 {{"jacobi", 9205},
                  {"gaussseidel", 4950},
                  {"southwell", 110400},
                  {"progressive", 110388},
                  {"gmres", 1}}},
          Expect{0.9999f, {{"gaussseidel", 49473}, {"gmres", 1}}}}) {
        Rig rig({diffuseShape("cube", Transform(), x.rho, 1.f, true)}, 1.f);
        REQUIRE(rig.mesh->elementCount() == 24u);
        auto ff = makeFormFactor("analytic", formFactorParams("analytic", {{"visibility_samples", std::int64_t(0)}}), rig.ctx);
        double E = rig.mesh->emission()[0];
        REQUIRE(E == Approx(Pi).epsilon(1e-6));
        // ρ as the mesh holds it (bin averages of the constant, in float).
        std::vector<double> expected(rig.mesh->radiosity().size());
        double delta = 0.0;
        auto [s0, s1] = rowSums(*rig.mesh, *ff);
        for (std::size_t ik = 0; ik < expected.size(); ++ik) {
            double rho = rig.mesh->reflectance()[ik];
            REQUIRE(rho == Approx(x.rho).epsilon(1e-6));
            expected[ik] = rig.mesh->emission()[ik] / (1.0 - rho);
            for (double s : {s0, s1}) delta = std::max(delta, std::abs((1.0 - rho) / (1.0 - rho * s) - 1.0));
        }
        std::vector<double> exact = directSolve(*rig.mesh, *ff);
        for (const auto& [name, count] : x.counts) {
            SolverReport r = makeSolver(name, 10000000, 1e-4)->solve(*rig.mesh, *ff, quiet());
            auto [mean, worst] = errorAgainst(*rig.mesh, expected);
            double truth = trueError(*rig.mesh, exact);
            INFO("ρ = " << x.rho << ", " << r.summary() << "; relative error against E/(1 − ρ): mean " << mean
                        << ", worst " << worst << "; δ " << delta << "; against the exact solution " << truth);
            CHECK(r.converged);
            CHECK(r.errorBound <= 1e-4);
            CHECK(truth <= r.errorBound + FloatStorage);
            CHECK(mean <= r.errorBound * (1.0 + delta) + delta + FloatStorage);
            CHECK(worst <= 3e-4 + delta);
            // The counts are deterministic; allow 2 % for round-off in the last digit of
            // the bound (Jacobi's is exact but for the rounding of ρ).
            CHECK(std::abs(double(r.iterations) - double(count)) <= std::max(1.0, 0.02 * double(count)));
            // The history is recorded and the residual decreases overall.
            REQUIRE(r.history.size() >= 1);
            CHECK(r.history.back().residual < 1e-4 * 1.0 / (1.0 - x.rho));
        }
    }
}

TEST_CASE("stiff: the reported error bound is honest, converged or stopped short", "[radiosity][stiff]") {
    // The true error Σ A|B − B*| / Σ A B* against the exact solution of the same system
    // must never exceed the reported bound (plus float storage of B), whether the solver
    // converged or hit max_iterations. Rooms:
    //  - a closed 2 × 2 × 8 box, one end emitting, six different reflectances from
    //    0.99 to 0.9999: stiff and not uniform;
    //  - the same with hemi-cube form factors, whose rows are not reciprocal (GMRES's
    //    symmetry argument fails; it must still converge, and the bound still hold);
    //  - the box open at one end with every wall white (ρ = 1): the naive contraction
    //    factor max ρ = 1 gives no bound; the weighted max-norm does (light escapes
    //    through the opening).
    struct Room {
        const char* name;
        std::vector<Ref<IShape>> shapes;
        std::string formFactor;
        bool open;
    };
    const std::array<float, 6> stiff = {0.99f, 0.9999f, 0.999f, 0.995f, 0.998f, 0.9995f};
    for (Room& room : std::vector<Room>{{"closed stiff box", box(4.f, stiff, 0), "analytic", false},
                                        {"closed stiff box, hemicube", box(4.f, stiff, 0), "hemicube", false},
                                        {"open white box", box(4.f, uniform(1.f), 0, 1), "analytic", true}}) {
        Rig rig(room.shapes, 1.f);
        // The hemi-cube at 32 pixels: coarse, so its rows are far from reciprocal, and
        // cheap (every solve recomputes the matrix).
        Properties fp = room.formFactor == "analytic"
                            ? formFactorParams("analytic", {{"visibility_samples", std::int64_t(0)}})
                            : formFactorParams(room.formFactor, {{"resolution", std::int64_t(32)}});
        auto ff = makeFormFactor(room.formFactor, fp, rig.ctx);
        std::vector<double> exact = directSolve(*rig.mesh, *ff);
        for (const std::string& name : AllSolvers)
            for (std::int64_t limit : {std::int64_t(3), std::int64_t(300), std::int64_t(10000000)}) {
                // In the stiff boxes only GMRES is run to convergence (the others need
                // 10⁴–10⁶ sweeps or relaxations there; the cube above covers them).
                if (limit > 300 && !room.open && name != "gmres") continue;
                SolverReport r = makeSolver(name, limit, 1e-4)->solve(*rig.mesh, *ff, quiet());
                double truth = trueError(*rig.mesh, exact);
                INFO(room.name << " (" << rig.mesh->elementCount() << " elements): " << r.summary()
                               << "; true error " << truth);
                CHECK(truth <= r.errorBound + FloatStorage);
                // Progressive refinement has no matrix to take ‖ρF‖ from and assumes max ρ:
                // no bound in the white box, where it stops on the residual instead.
                bool unbounded = name == "progressive" && room.open;
                if (unbounded) CHECK(r.errorBound == std::numeric_limits<double>::infinity());
                if (limit > 300) {
                    CHECK(r.converged);
                    if (!unbounded) CHECK(r.errorBound <= 1e-4);
                }
                for (float b : rig.mesh->radiosity()) CHECK((std::isfinite(b) && b >= 0.f));
            }
    }
}

TEST_CASE("stiff: gmres needs few iterations as ρ → 1, relaxation 1/(1 − ρ) times more", "[radiosity][stiff]") {
    // The closed 2 × 2 × 8 box of uniform ρ, one end emitting (72 elements). The light
    // reaches the far end only after many bounces, and the system's stiffness sits in
    // the nearly uniform modes, which GMRES's Krylov space captures in a few steps.
    // Measured (bound ≤ 1e-4):
    //   ρ         gmres (products)   gaussseidel (sweeps)
    //   0.99          10                    443
    //   0.999         10                   2280
    //   0.9999        10                   3890 (left out here: 0.1 s)
    // Checked: gmres converges with a bound ≤ τ, the true error is within it, and its
    // count never exceeds twice that at 0.99, while Gauss–Seidel's count grows more than
    // threefold from 0.99 to 0.999.
    std::uint64_t first = 0, gs = 0;
    for (float rho : {0.99f, 0.999f, 0.9999f}) {
        Rig rig(box(4.f, uniform(rho), 0), 1.f);
        auto ff = makeFormFactor("analytic", formFactorParams("analytic", {{"visibility_samples", std::int64_t(0)}}), rig.ctx);
        std::vector<double> exact = directSolve(*rig.mesh, *ff);
        SolverReport r = makeSolver("gmres", 1000, 1e-4)->solve(*rig.mesh, *ff, quiet());
        double truth = trueError(*rig.mesh, exact);
        INFO("ρ = " << rho << ": " << r.summary() << "; true error " << truth);
        CHECK(r.converged);
        CHECK(truth <= r.errorBound + FloatStorage);
        if (!first) first = r.iterations;
        CHECK(r.iterations <= 2 * first);
        if (rho < 0.9995f) {
            SolverReport g = makeSolver("gaussseidel", 10000000, 1e-4)->solve(*rig.mesh, *ff, quiet());
            INFO(g.summary());
            CHECK(g.converged);
            if (gs) CHECK(g.iterations >= 3 * gs);
            gs = g.iterations;
        }
    }
}

TEST_CASE("stiff: stopping at the iteration limit is reported, never silent", "[radiosity][stiff]") {
    Rig rig({diffuseShape("cube", Transform(), 0.999f, 1.f, true)}, 1.f);
    auto ff = makeFormFactor("analytic", formFactorParams("analytic", {{"visibility_samples", std::int64_t(0)}}), rig.ctx);
    for (const std::string name : {"jacobi", "gaussseidel", "southwell", "progressive"}) {
        SolverReport r = makeSolver(name, 1000, 1e-4)->solve(*rig.mesh, *ff, quiet());
        INFO(r.summary());
        CHECK_FALSE(r.converged);
        CHECK(r.iterations == 1000u);
        CHECK(r.residual > 1e-4);
        CHECK(r.errorBound > 1e-4);
        std::string s = r.summary();
        CHECK(s.find("solver '" + name + "'") != std::string::npos);
        CHECK(s.find("did not converge") != std::string::npos);
        CHECK(s.find("max_iterations = 1000") != std::string::npos);
        CHECK(s.find(fmt::format("{:.3g}", r.residual)) != std::string::npos);
        CHECK(s.find(fmt::format("error bound {:.3g}", r.errorBound)) != std::string::npos);
        if (name == "jacobi") CHECK(r.residual == Approx(std::pow(0.999, 1000)).epsilon(1e-3));  // ρ^k
        // B is still the partial sum: finite and below the solution, 1000 π; progressive
        // refinement adds the ambient term, which in a uniform enclosure is the exact
        // remainder, so its display estimate is already close to the solution.
        auto [mean, worst] = errorAgainst(*rig.mesh, 1000.0 * Pi);
        INFO("mean relative error " << mean << ", worst " << worst);
        CHECK(mean <= r.errorBound + 1e-3);  // 1e-3: ρ is 0.999 in float, not exactly
        for (float b : rig.mesh->radiosity()) CHECK((std::isfinite(b) && b > 0.f));
        if (name == "progressive") CHECK(worst < 0.01);
        else
            for (float b : rig.mesh->radiosity()) CHECK(b < 1000.f * Pi);
    }
    SECTION("gmres, in a room it cannot solve in two steps") {
        Rig room(box(4.f, uniform(0.999f), 0), 1.f);
        auto f = makeFormFactor("analytic", formFactorParams("analytic", {{"visibility_samples", std::int64_t(0)}}), room.ctx);
        SolverReport r = makeSolver("gmres", 2, 1e-4)->solve(*room.mesh, *f, quiet());
        INFO(r.summary());
        CHECK_FALSE(r.converged);
        CHECK(r.iterations == 2u);
        CHECK(r.errorBound > 1e-4);
        CHECK(r.summary().find("did not converge") != std::string::npos);
        CHECK(r.summary().find("max_iterations = 2") != std::string::npos);
    }
}

TEST_CASE("stiff: a closed white room is reported as (nearly) singular, never with a false bound",
          "[radiosity][stiff]") {
    // ρ = 1 in a closed enclosure: I − ρF is singular when rows sum to 1, and B grows
    // without bound. In float the rows sum to 1 − O(1e-8), so the system solved is
    // nonsingular with B ~ 1e7 E, set by round-off (the error bound warns). Whatever each
    // solver returns, it is finite and the true error against the exact solution of the
    // same system is within the reported bound (+ 1e-6: the direct solve's own accuracy
    // at condition ~1e8).
    Rig rig({diffuseShape("cube", Transform(), 1.f, 1.f, true)}, 1.f);
    auto ff = makeFormFactor("analytic", formFactorParams("analytic", {{"visibility_samples", std::int64_t(0)}}), rig.ctx);
    std::vector<double> exact = directSolve(*rig.mesh, *ff);
    for (const std::string& name : AllSolvers) {
        SolverReport r = makeSolver(name, 50, 1e-4)->solve(*rig.mesh, *ff, quiet());
        double truth = trueError(*rig.mesh, exact);
        INFO(r.summary() << "; true error " << truth);
        CHECK(truth <= r.errorBound + FloatStorage + 1e-6);
        if (name != "gmres") CHECK_FALSE(r.converged);  // 50 sweeps are 50 bounces of 10⁷
        for (float b : rig.mesh->radiosity()) CHECK(std::isfinite(b));
    }
}
