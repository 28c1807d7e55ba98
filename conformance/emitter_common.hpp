#pragma once
// What the emitter suite's files share (emitter_suite.cpp: setup, direct sampling,
// extreme points; emitter_emission.cpp: emission, power, inverse-square law): the
// emitter under test with its host shape and reference points, tolerances, and small
// spectrum helpers.
#include "conformance/conformance.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace effigi::conform::emitter {

/// Densities above this (sr⁻¹) are narrower than the histogram can resolve.
constexpr double MaxEmitterPdf = 1000.0;
/// Relative agreement asked of two float computations of the same value.
constexpr double ValueTolerance = 1e-3;
/// Relative agreement asked of power(), which IEmitter documents as approximate.
constexpr double PowerTolerance = 0.25;

/// The surface a surface emitter is nested in: the square [-½, ½]² at z = 0 (normal +z)
/// or the sphere of radius ½ about the origin (normal outward).
struct Host {
    std::string name;
    Ref<IShape> shape;
    bool sphere = false;
};

/// One emitter ready to query, with the reference points of its direct-sampling checks.
struct Setup {
    Ref<IEmitter> emitter;
    Host host;  // shape null: not a surface emitter
    std::vector<Point3f> refs;
    std::string at;  // suffix of the check names ("" or " on square"/" on sphere")
};

inline const BBox3f SceneBounds(Point3f(-1.f), Point3f(1.f));

inline bool valid(const SampledSpectrum& s) {
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (!(std::isfinite(s[i]) && s[i] >= 0.f)) return false;
    return true;
}
inline bool positive(const SampledSpectrum& s) {
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (s[i] > 0.f) return true;
    return false;
}
inline double relError(double a, double b) {
    double m = std::max(std::abs(a), std::abs(b));
    return m > 1e-30 ? std::abs(a - b) / m : 0.0;
}
inline double relError(const SampledSpectrum& a, const SampledSpectrum& b) {
    double e = 0.0;
    for (int i = 0; i < NSpectrumSamples; ++i) e = std::max(e, relError(a[i], b[i]));
    return e;
}
inline Point2f uniform2(PCG32& rng) { return Point2f(rng.nextFloat(), rng.nextFloat()); }
/// sampleEmission(): values, pdfs and ray origins, and the flux against power() (or, for
/// lights at infinity, against their radiance).
void checkEmission(Target& t, const Setup& s);
/// Point-like emitters: L · dist² along emitted rays against the emitted intensity.
void checkInverseSquare(Target& t, const Setup& s);

} // namespace effigi::conform::emitter
