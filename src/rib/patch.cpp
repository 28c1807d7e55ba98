// RIB patches: Patch "bilinear" | "bicubic" and the Basis they use (RenderMan Interface
// 3.2, §5.7). A patch becomes a 16 × 16 grid of triangles with the patch's own normals
// (∂P/∂u × ∂P/∂v); its points are given with u varying fastest. PatchMesh (patch grids
// with wrap modes) is not supported.
#include "state.hpp"
#include "tessellate.hpp"

#include "effigi/core/input.hpp"

#include <algorithm>

namespace effigi::rib {

bool namedBasis(const std::string& name, Basis& m) {
    // Row-major, as P(u) = [u³ u² u 1] · B · [P0 P1 P2 P3]ᵀ (RI 3.2, §5.7).
    static const std::pair<const char*, Basis> bases[] = {
        {"bezier", {-1, 3, -3, 1, 3, -6, 3, 0, -3, 3, 0, 0, 1, 0, 0, 0}},
        {"b-spline", {-1 / 6., 3 / 6., -3 / 6., 1 / 6., 3 / 6., -6 / 6., 3 / 6., 0, -3 / 6., 0, 3 / 6., 0, 1 / 6.,
                      4 / 6., 1 / 6., 0}},
        {"catmull-rom", {-.5, 1.5, -1.5, .5, 1, -2.5, 2, -.5, -.5, 0, .5, 0, 0, 1, 0, 0}},
        {"hermite", {2, 1, -2, 1, -3, -2, 3, -1, 0, 1, 0, 0, 1, 0, 0, 0}},
        {"power", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},
    };
    for (const auto& [n, b] : bases)
        if (name == n) return (m = b, true);
    return false;
}

namespace {

/// The four weights of a basis at t, and their derivatives.
void weights(const Basis& b, double t, double w[4], double dw[4]) {
    const double T[4] = {t * t * t, t * t, t, 1.0}, dT[4] = {3.0 * t * t, 2.0 * t, 1.0, 0.0};
    for (int i = 0; i < 4; ++i) {
        w[i] = dw[i] = 0.0;
        for (int k = 0; k < 4; ++k) w[i] += T[k] * b[4 * k + i], dw[i] += dT[k] * b[4 * k + i];
    }
}

Basis basisArg(Args& a, const char* which) {
    Basis b{};
    if (a.atParams()) {
        std::string name = a.string(which);
        if (!namedBasis(name, b))
            a.fail("basis '{}' is not supported (bezier, b-spline, catmull-rom, hermite, power, or 16 numbers)",
                   excerpt(name));
    } else {
        std::vector<double> v = a.array(which);
        if (v.size() != 16) a.fail("a basis matrix has 16 numbers, got {}", v.size());
        std::copy(v.begin(), v.end(), b.begin());
    }
    std::vector<double> step = a.array("basis step");
    if (step.size() != 1 || !(step[0] >= 1.0)) a.fail("a basis step is one number >= 1");
    return b;  // the step only matters to PatchMesh, which is not supported
}

} // namespace

void reqBasis(State& s, Args& a) {
    Basis u = basisArg(a, "u basis"), v = basisArg(a, "v basis");
    a.end();
    s.attr.basisU = u;
    s.attr.basisV = v;
}

void reqPatch(State& s, Args& a) {
    const std::string type = a.string("patch type");
    a.setLabel(fmt::format("Patch \"{}\"", excerpt(type)));
    const bool bicubic = type == "bicubic";
    if (!bicubic && type != "bilinear") a.fail("patch type '{}' is not supported (bilinear and bicubic are)", excerpt(type));
    Params p = a.params();
    const std::vector<double>* P = p.numbers("P", 3);
    const std::vector<double>* st = p.numbers("st", 2);
    p.finish();
    const std::size_t n = bicubic ? 16 : 4;
    if (!P) a.fail("parameter 'P' is required");
    if (P->size() != 3 * n) a.fail("'P' has {} points where {} are needed", P->size() / 3, n);
    if (st && st->size() != 8) a.fail("'st' has {} pairs where 4 (the corners) are needed", st->size() / 2);
    // Bilinear: the linear basis on each axis (weights 1 − t, t).
    const Basis linear{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 1, 0, 0, 1, 0};
    const Basis& bu = bicubic ? s.attr.basisU : linear;
    const Basis& bv = bicubic ? s.attr.basisV : linear;
    const int k = bicubic ? 4 : 2;
    auto point = [&](int i, int j) {
        const double* q = &(*P)[3 * std::size_t(bicubic ? 4 * j + i : 2 * j + i)];
        return Vector3d(q[0], q[1], q[2]);
    };
    auto basisIndex = [&](int i) { return bicubic ? i : i + 2; };  // linear weights sit in columns 2, 3
    TriangleMesh m = gridMesh(16, 16, [&](double u, double v, Vector3d& pos, Vector3d& nrm) {
        double wu[4], dwu[4], wv[4], dwv[4];
        weights(bu, u, wu, dwu);
        weights(bv, v, wv, dwv);
        Vector3d du(0.0), dv(0.0);
        pos = Vector3d(0.0);
        for (int j = 0; j < k; ++j)
            for (int i = 0; i < k; ++i) {
                const int a2 = basisIndex(i), b2 = basisIndex(j);
                pos += wu[a2] * wv[b2] * point(i, j);
                du += dwu[a2] * wv[b2] * point(i, j);
                dv += wu[a2] * dwv[b2] * point(i, j);
            }
        nrm = glm::cross(du, dv);
    });
    if (st)
        for (Point2f& uv : m.uvs) {
            const double u = uv.x, v = uv.y;
            auto c = [&](int i) { return Vector2f(float((*st)[2 * i]), float((*st)[2 * i + 1])); };
            uv = float((1 - u) * (1 - v)) * c(0) + float(u * (1 - v)) * c(1) + float((1 - u) * v) * c(2) +
                 float(u * v) * c(3);
        }
    addMesh(s, a, std::move(m), false);
}

} // namespace effigi::rib
