// Build-time tool: fits the RGB -> spectrum coefficient table of
//   W. Jakob and J. Hanika, "A Low-Dimensional Function Space for Efficient Spectral
//   Upsampling", Computer Graphics Forum 38(2), 2019,
// for linear sRGB (Rec.709 primaries, D65 white).
//
// A reflectance r(λ) = s(c0 λ² + c1 λ + c2), s(x) = ½ + x / (2√(1+x²)), is fitted per
// table cell so that r rendered under D65 and converted to linear sRGB matches the
// cell's RGB. The residual is measured in CIELAB (white = D65 under the same
// integration), minimised with Gauss–Newton steps (finite-difference Jacobian, 3×3 LU
// with partial pivoting) and a backtracking safeguard.
//
// Table layout (paper §4): the cube is split into three slabs by the index l of the
// largest component. In slab l a cell (xi, yi, zi) stands for rgb[l] = z,
// rgb[l+1] = x·z, rgb[l+2] = y·z (indices mod 3), x, y = i/(res−1) and
// z = smoothstep(smoothstep(k/(res−1))), which puts more nodes near black and white
// where the coefficients change fastest. Every (l, xi, yi) column is solved by
// continuation along z: from the centre outward, each solve starting at its
// neighbour's solution.
//
// Output (little endian): "EFFIGI_RGB2SPEC\0", int32 res, float zNodes[res],
// float coeffs[3][res][res][res][3] indexed [l][zi][yi][xi][c], with the coefficients
// of a polynomial in λ measured in nm.
//
// Usage: rgb2spec_opt <res> <output.bin>
#include "effigi/spectral/cie.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

namespace {

using effigi::cie::TableSize;
constexpr double LambdaLo = 360.0, LambdaHi = 830.0;

// Linear sRGB -> XYZ, the same matrix as effigi/spectral/colorspace.hpp.
constexpr double RgbToXyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                   {0.2126729, 0.7151522, 0.0721750},
                                   {0.0193339, 0.1191920, 0.9503041}};
// Its inverse as used by the renderer (XYZ -> linear sRGB), to report RGB errors.
constexpr double XyzToRgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                   {-0.9692660, 1.8760108, 0.0415560},
                                   {0.0556434, -0.2040259, 1.0572252}};

/// Weights w_c[i] such that Σ_i r(t_i) w_c[i] = XYZ_c of the reflectance r under D65,
/// normalised so that r ≡ 1 has Y = 1. t is wavelength mapped to [0, 1] over
/// 360–830 nm: the fit is far better conditioned there than in nm.
struct Quadrature {
    std::vector<double> t, w[3];
};

/// The renderer's reference integral: trapezoid rule on the 1 nm tables.
Quadrature fineQuadrature() {
    Quadrature q;
    double norm = 0.0;
    for (int i = 0; i < TableSize; ++i) {
        double h = (i == 0 || i == TableSize - 1) ? 0.5 : 1.0;
        double d = h * effigi::cie::D65[i];
        q.t.push_back(double(i) / double(TableSize - 1));
        q.w[0].push_back(d * effigi::cie::X[i]);
        q.w[1].push_back(d * effigi::cie::Y[i]);
        q.w[2].push_back(d * effigi::cie::Z[i]);
        norm += d * effigi::cie::Y[i];
    }
    for (auto& wc : q.w)
        for (double& v : wc) v /= norm;
    return q;
}

/// A coarser rule for the bulk of the iterations: r is sampled every `step` nm and
/// interpolated linearly in between, and that interpolant is integrated exactly
/// against the fine rule (each fine weight is split between its two coarse
/// neighbours). Since r is smooth this is close to the fine rule at a fraction of
/// the cost; the fine rule then polishes the result.
Quadrature coarseQuadrature(const Quadrature& fine, int step) {
    int n = (TableSize - 1) / step + 1;
    Quadrature q;
    q.t.resize(n);
    for (auto& wc : q.w) wc.assign(n, 0.0);
    for (int k = 0; k < n; ++k) q.t[k] = double(k * step) / double(TableSize - 1);
    for (int i = 0; i < TableSize; ++i) {
        int k = std::min(i / step, n - 2);
        double f = double(i - k * step) / double(step);
        for (int c = 0; c < 3; ++c) {
            q.w[c][k] += (1.0 - f) * fine.w[c][i];
            q.w[c][k + 1] += f * fine.w[c][i];
        }
    }
    return q;
}

void integrate(const Quadrature& q, const double c[3], double xyz[3]) {
    double X = 0.0, Y = 0.0, Z = 0.0;
    const std::size_t n = q.t.size();
    const double *t = q.t.data(), *wx = q.w[0].data(), *wy = q.w[1].data(), *wz = q.w[2].data();
    for (std::size_t i = 0; i < n; ++i) {
        double x = (c[0] * t[i] + c[1]) * t[i] + c[2];
        double r = 0.5 + 0.5 * x / std::sqrt(1.0 + x * x);
        X += r * wx[i];
        Y += r * wy[i];
        Z += r * wz[i];
    }
    xyz[0] = X;
    xyz[1] = Y;
    xyz[2] = Z;
}

/// CIE 1976 L*a*b* (CIE 15:2004 §8.2.1) relative to the white `wp`.
void xyzToLab(const double xyz[3], const double wp[3], double lab[3]) {
    auto f = [](double v) {
        constexpr double d = 6.0 / 29.0;
        return v > d * d * d ? std::cbrt(v) : v / (3.0 * d * d) + 4.0 / 29.0;
    };
    double fx = f(xyz[0] / wp[0]), fy = f(xyz[1] / wp[1]), fz = f(xyz[2] / wp[2]);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

struct Problem {
    const Quadrature* q;
    double white[3];
    double targetLab[3];

    /// Lab residual of coefficients c; returns its Euclidean norm (CIE76 ΔE).
    double residual(const double c[3], double res[3]) const {
        double xyz[3], lab[3];
        integrate(*q, c, xyz);
        xyzToLab(xyz, white, lab);
        for (int i = 0; i < 3; ++i) res[i] = lab[i] - targetLab[i];
        return std::sqrt(res[0] * res[0] + res[1] * res[1] + res[2] * res[2]);
    }
};

/// Solves A x = b in place (b becomes x) by LU decomposition with partial pivoting.
bool solve3(double A[3][3], double b[3]) {
    int perm[3] = {0, 1, 2};
    for (int k = 0; k < 3; ++k) {
        int p = k;
        for (int i = k + 1; i < 3; ++i)
            if (std::abs(A[i][k]) > std::abs(A[p][k])) p = i;
        if (!(std::abs(A[p][k]) > 1e-15)) return false;
        if (p != k) {
            std::swap(A[p], A[k]);
            std::swap(perm[p], perm[k]);
        }
        for (int i = k + 1; i < 3; ++i) {
            A[i][k] /= A[k][k];
            for (int j = k + 1; j < 3; ++j) A[i][j] -= A[i][k] * A[k][j];
        }
    }
    double y[3];
    for (int i = 0; i < 3; ++i) {
        y[i] = b[perm[i]];
        for (int j = 0; j < i; ++j) y[i] -= A[i][j] * y[j];
    }
    for (int i = 2; i >= 0; --i) {
        for (int j = i + 1; j < 3; ++j) y[i] -= A[i][j] * y[j];
        y[i] /= A[i][i];
    }
    std::copy(y, y + 3, b);
    return std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]);
}

/// Gauss–Newton on the 3×3 Lab residual of P; c holds the start and receives the
/// result. The finite-difference Jacobian is taken from J, which may be a cheaper model
/// of the same residual (the coarse quadrature): near the solution a slightly wrong
/// Jacobian only slows quadratic convergence to fast linear convergence, while every
/// residual, and so the result, is P's own. A full step is taken whenever it reduces
/// ΔE, else it is halved (the plain method of the paper, guarded for cells far from
/// their start). Returns the final ΔE.
double gaussNewton(const Problem& P, const Problem& J, double c[3], int maxIter, double tol) {
    double r[3];
    double err = P.residual(c, r);
    for (int it = 0; it < maxIter && err > tol; ++it) {
        double rj[3], A[3][3];
        const double* r0 = r;
        if (&J != &P) {
            J.residual(c, rj);
            r0 = rj;
        }
        for (int j = 0; j < 3; ++j) {
            double h = 1e-7 * std::max(1.0, std::abs(c[j]));
            double cp[3] = {c[0], c[1], c[2]}, rp[3];
            cp[j] += h;
            J.residual(cp, rp);
            for (int i = 0; i < 3; ++i) A[i][j] = (rp[i] - r0[i]) / h;
        }
        double d[3] = {-r[0], -r[1], -r[2]};
        if (!solve3(A, d)) break;
        bool improved = false;
        for (double step = 1.0; step > 1e-4; step *= 0.5) {
            double cn[3] = {c[0] + step * d[0], c[1] + step * d[1], c[2] + step * d[2]}, rn[3];
            double en = P.residual(cn, rn);
            if (en < err) {
                std::copy(cn, cn + 3, c);
                std::copy(rn, rn + 3, r);
                err = en;
                improved = true;
                break;
            }
        }
        if (!improved) break;
    }
    return err;
}

double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

/// Coefficients of A t² + B t + C, t = (λ − 360)/470, as a polynomial in λ [nm].
void toNanometres(const double c[3], float out[3]) {
    const double a = 1.0 / (LambdaHi - LambdaLo), b = -LambdaLo / (LambdaHi - LambdaLo);
    out[0] = float(c[0] * a * a);
    out[1] = float(2.0 * c[0] * a * b + c[1] * a);
    out[2] = float(c[0] * b * b + c[1] * b + c[2]);
}

void putU32(std::vector<unsigned char>& buf, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) buf.push_back(static_cast<unsigned char>(v >> (8 * i)));
}
void putFloat(std::vector<unsigned char>& buf, float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    putU32(buf, u);
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: rgb2spec_opt <resolution> <output.bin>\n");
        return 1;
    }
    const int res = std::atoi(argv[1]);
    if (res < 2 || res > 256) {
        std::fprintf(stderr, "rgb2spec_opt: resolution must be in [2, 256], got '%s'\n", argv[1]);
        return 1;
    }
    const char* outPath = argv[2];
    // Open the output first so that a bad path fails before the long fit.
    std::ofstream out(outPath, std::ios::binary | std::ios::trunc);
    if (!out) {
        std::fprintf(stderr, "rgb2spec_opt: cannot open '%s' for writing\n", outPath);
        return 1;
    }
    std::printf("rgb2spec_opt: fitting 3 x %d^3 sigmoid polynomials for sRGB\n", res);
    std::fflush(stdout);
    auto t0 = std::chrono::steady_clock::now();

    const Quadrature fine = fineQuadrature();
    const Quadrature coarse = coarseQuadrature(fine, 5);
    double white[3] = {0.0, 0.0, 0.0};  // XYZ of r ≡ 1: the Lab white point (Y = 1)
    for (int c = 0; c < 3; ++c)
        for (double w : fine.w[c]) white[c] += w;

    std::vector<float> zNodes(res);
    for (int k = 0; k < res; ++k) zNodes[k] = float(smoothstep(smoothstep(double(k) / (res - 1))));

    const std::size_t cells = std::size_t(res) * res * res;
    std::vector<float> coeffs(3 * cells * 3);
    const int startK = res / 2;  // slab centre: mid brightness, where the fit is easiest

    std::atomic<int> columnsDone{0};
    std::atomic<int> lastReported{0};
    std::mutex statsMutex;
    double worstRgb = 0.0, worstLab = 0.0;
    long unconverged = 0;
    const int columns = 3 * res * res;

    tbb::parallel_for(0, columns, [&](int col) {
        const int l = col / (res * res), yi = (col / res) % res, xi = col % res;
        const double x = double(xi) / (res - 1), y = double(yi) / (res - 1);
        double localRgb = 0.0, localLab = 0.0;
        long localBad = 0;

        auto solveCell = [&](int k, double c[3]) {
            const double z = zNodes[k];
            double rgb[3];
            rgb[l] = z;
            rgb[(l + 1) % 3] = x * z;
            rgb[(l + 2) % 3] = y * z;
            double xyz[3];
            for (int i = 0; i < 3; ++i)
                xyz[i] = RgbToXyz[i][0] * rgb[0] + RgbToXyz[i][1] * rgb[1] + RgbToXyz[i][2] * rgb[2];
            Problem coarseP{&coarse, {white[0], white[1], white[2]}, {}};
            xyzToLab(xyz, white, coarseP.targetLab);
            Problem fineP = coarseP;
            fineP.q = &fine;
            // Converge on the cheap model (it differs from the fine one by ΔE < 0.5),
            // then polish against the renderer's own integral.
            gaussNewton(coarseP, coarseP, c, 50, 1e-3);
            double err = gaussNewton(fineP, coarseP, c, 30, 1e-7);
            if (err > 1e-5) err = gaussNewton(fineP, fineP, c, 20, 1e-7);  // rare: near black

            // Report the RGB error of the fitted cell (the quantity users see).
            double fxyz[3];
            integrate(fine, c, fxyz);
            double e = 0.0;
            for (int i = 0; i < 3; ++i) {
                double v = XyzToRgb[i][0] * fxyz[0] + XyzToRgb[i][1] * fxyz[1] + XyzToRgb[i][2] * fxyz[2];
                e = std::max(e, std::abs(v - rgb[i]));
            }
            if (k > 0) {  // black (z = 0) lies at c2 = −∞ and is never reached
                localRgb = std::max(localRgb, e);
                localLab = std::max(localLab, err);
                if (err > 1e-3) ++localBad;
            }
            std::size_t idx = ((((std::size_t(l) * res + k) * res + yi) * res) + xi) * 3;
            toNanometres(c, &coeffs[idx]);
        };

        double c[3] = {0.0, 0.0, 0.0}, cStart[3];
        for (int k = startK; k < res; ++k) {
            solveCell(k, c);
            if (k == startK) std::copy(c, c + 3, cStart);
        }
        std::copy(cStart, cStart + 3, c);
        for (int k = startK - 1; k >= 0; --k) solveCell(k, c);

        {
            std::lock_guard<std::mutex> lock(statsMutex);
            worstRgb = std::max(worstRgb, localRgb);
            worstLab = std::max(worstLab, localLab);
            unconverged += localBad;
        }
        int done = ++columnsDone;
        int pct = int(100L * done / columns) / 10 * 10;
        int prev = lastReported.load();
        while (pct > prev && !lastReported.compare_exchange_weak(prev, pct)) {
        }
        if (pct > prev) {
            std::printf("rgb2spec_opt: %3d%%\n", pct);
            std::fflush(stdout);
        }
    });

    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("rgb2spec_opt: %d^3 x 3 cells in %.1f s; max dE76 %.2e, max |dRGB| %.2e, "
                "%ld cells with dE > 1e-3\n",
                res, secs, worstLab, worstRgb, unconverged);

    std::vector<unsigned char> buf;
    buf.reserve(16 + 4 + 4 * (zNodes.size() + coeffs.size()));
    const char magic[16] = "EFFIGI_RGB2SPEC";  // 15 characters and the terminating '\0'
    buf.insert(buf.end(), magic, magic + 16);
    putU32(buf, std::uint32_t(res));
    for (float z : zNodes) putFloat(buf, z);
    for (float v : coeffs) putFloat(buf, v);

    out.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size()));
    out.close();
    if (!out) {
        std::fprintf(stderr, "rgb2spec_opt: error writing '%s'\n", outPath);
        std::remove(outPath);  // no truncated table left behind
        return 1;
    }
    return 0;
}
