// Fresnel reflectance (effigi/render/fresnel.hpp) against values computed independently
// here: Fresnel's sine/tangent laws for dielectrics, the real-arithmetic (a, b) form of
// the conductor equations, and published normal-incidence numbers; total internal
// reflection; finiteness at the numerically hard corners; the specular directions.
#include "effigi/render/fresnel.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace effigi;

namespace {

constexpr double DegToRad = 3.14159265358979323846 / 180.0;
const double TestAngles[] = {0.0, 45.0, 89.9};

/// Dielectric reflectance from Fresnel's laws in angle form (Born & Wolf §1.5, eq. 21a/b):
/// r_s = −sin(θi − θt)/sin(θi + θt), r_p = tan(θi − θt)/tan(θi + θt); at normal
/// incidence (0/0) the limit ((n − 1)/(n + 1))².
double dielectricReference(double thetaDeg, double n) {
    if (thetaDeg == 0.0) return std::pow((n - 1.0) / (n + 1.0), 2.0);
    double ti = thetaDeg * DegToRad;
    double st = std::sin(ti) / n;
    if (st >= 1.0) return 1.0;
    double tt = std::asin(st);
    double rs = -std::sin(ti - tt) / std::sin(ti + tt);
    double rp = std::tan(ti - tt) / std::tan(ti + tt);
    return 0.5 * (rs * rs + rp * rp);
}

/// Conductor reflectance in the real form with a² + b² = |n² − sin²θ| (e.g. Lazányi &
/// Szirmay-Kalos 2005, eqs. 2-3, after Born & Wolf §14.2): no complex arithmetic, so an
/// independent check of the complex evaluation.
double conductorReference(double thetaDeg, double eta, double k) {
    long double t = thetaDeg * DegToRad, c = std::cos(t), s2 = std::sin(t) * std::sin(t);
    long double e = eta, kk = k;
    long double re = e * e - kk * kk - s2;
    long double a2b2 = std::sqrt(re * re + 4 * e * e * kk * kk);
    long double a = std::sqrt(std::max<long double>(0, 0.5L * (a2b2 + re)));
    long double Rs = (a2b2 - 2 * a * c + c * c) / (a2b2 + 2 * a * c + c * c);
    long double Rp = Rs * (c * c * a2b2 - 2 * a * c * s2 + s2 * s2) / (c * c * a2b2 + 2 * a * c * s2 + s2 * s2);
    return double(0.5L * (Rs + Rp));
}

} // namespace

TEST_CASE("fresnel: dielectric matches Fresnel's laws at 0, 45 and 89.9 degrees", "[fresnel]") {
    for (double n : {1.0001, 1.333, 1.5, 2.42}) {
        for (double deg : TestAngles) {
            // The reference sees exactly the float inputs the function gets: near grazing
            // with η ≈ 1 the reflectance depends on η − 1 to all its digits.
            float c = float(std::cos(deg * DegToRad)), e = float(n);
            float F = fresnelDielectric(c, e);
            double ref = dielectricReference(std::acos(double(c)) / DegToRad, double(e));
            INFO("n = " << n << ", theta = " << deg << ": " << F << " vs " << ref);
            // float evaluation of a double formula: 1e-6 absolute plus 1e-5 relative.
            CHECK(std::abs(F - ref) <= 1e-6 + 1e-5 * ref);
        }
    }
}

TEST_CASE("fresnel: dielectric published values", "[fresnel]") {
    // Normal incidence ((n − 1)/(n + 1))²: glass 1.5 → 4 %, water 1.333 → 2.04 %,
    // diamond 2.42 → 17.2 % (the textbook values, e.g. Hecht, Optics, ch. 4).
    CHECK(fresnelDielectric(1.f, 1.5f) == Approx(0.04).margin(1e-7));
    CHECK(fresnelDielectric(1.f, 1.333f) == Approx(0.0203732).margin(1e-6));
    CHECK(fresnelDielectric(1.f, 2.42f) == Approx(0.1723949).margin(1e-6));
    // n = 1.5 at 45°: R_s = 0.0920, R_p = 0.00847 (the textbook example), mean 0.05024.
    CHECK(fresnelDielectric(std::cos(float(45 * DegToRad)), 1.5f) == Approx(0.050240).margin(2e-6));
    // Brewster's angle atan(n): R_p = 0, so F = R_s/2 = ½ ((n² − 1)/(n² + 1))².
    float tb = std::atan(1.5f);
    CHECK(fresnelDielectric(std::cos(tb), 1.5f) == Approx(0.5 * std::pow((2.25 - 1) / (2.25 + 1), 2)).margin(1e-6));
    // The same interface seen from the inside at the refracted angle reflects the same.
    float ci = std::cos(0.6f), st = std::sin(0.6f) / 1.5f, ct = std::sqrt(1 - st * st);
    CHECK(fresnelDielectric(-ct, 1.5f) == Approx(fresnelDielectric(ci, 1.5f)).epsilon(1e-5));
    // No interface, no reflection.
    CHECK(fresnelDielectric(0.3f, 1.f) == 0.f);
}

TEST_CASE("fresnel: total internal reflection beyond the critical angle", "[fresnel]") {
    const float n = 1.5f;
    const double critical = std::asin(1.0 / n) / DegToRad;  // 41.81°
    for (double deg : {42.0, 50.0, 70.0, 89.9}) {
        INFO("inside, theta = " << deg);
        CHECK(fresnelDielectric(-float(std::cos(deg * DegToRad)), n) == 1.f);
        Vector3f wt(0.f);
        float etaRel = 0.f;
        Vector3f wi(float(std::sin(deg * DegToRad)), 0.f, -float(std::cos(deg * DegToRad)));
        CHECK_FALSE(refractLocal(wi, n, wt, etaRel));
    }
    float below = fresnelDielectric(-float(std::cos((critical - 0.5) * DegToRad)), n);
    CHECK(below < 1.f);
    CHECK(below > 0.3f);  // it rises steeply toward the critical angle
    // Equivalent exterior/interior pair: η < 1 seen from outside is TIR too.
    CHECK(fresnelDielectric(float(std::cos(60 * DegToRad)), 1.f / n) == 1.f);
}

TEST_CASE("fresnel: conductor matches the real-arithmetic form", "[fresnel]") {
    struct Case { double eta, k; };
    for (Case m : {Case{0.2, 3.0}, Case{4.0, 10.0}, Case{1.0001, 0.0}, Case{1.0001, 0.5}, Case{0.0, 1.0}}) {
        for (double deg : TestAngles) {
            float c = float(std::cos(deg * DegToRad));
            float F = fresnelConductor(c, float(m.eta), float(m.k));
            double ref = conductorReference(std::acos(double(c)) / DegToRad, double(float(m.eta)), double(float(m.k)));
            INFO("eta = " << m.eta << ", k = " << m.k << ", theta = " << deg << ": " << F << " vs " << ref);
            CHECK(std::abs(F - ref) <= 1e-6 + 1e-5 * ref);
        }
        // Published normal-incidence value |(n − 1 + ik)/(n + 1 + ik)|² = ((η−1)² + k²)/((η+1)² + k²).
        double normal = ((m.eta - 1) * (m.eta - 1) + m.k * m.k) / ((m.eta + 1) * (m.eta + 1) + m.k * m.k);
        CHECK(fresnelConductor(1.f, float(m.eta), float(m.k)) == Approx(normal).margin(1e-7));
    }
    // η = 0.2, k = 3 (silver-like): 92.34 % at normal incidence.
    CHECK(fresnelConductor(1.f, 0.2f, 3.f) == Approx(9.64 / 10.44).epsilon(1e-6));
    // k = 0 reduces to the dielectric formula.
    for (double deg : TestAngles) {
        float c = float(std::cos(deg * DegToRad));
        CHECK(fresnelConductor(c, 1.5f, 0.f) == Approx(fresnelDielectric(c, 1.5f)).epsilon(1e-5).margin(1e-7));
    }
    // Mitsuba's "none" material (η = 0, k = 1) is a perfect mirror at every angle.
    for (double deg : {0.0, 30.0, 60.0, 89.9}) CHECK(fresnelConductor(float(std::cos(deg * DegToRad)), 0.f, 1.f) == Approx(1.0).margin(1e-6));
}

TEST_CASE("fresnel: finite and in [0, 1] at the extremes", "[fresnel]") {
    for (float c : {1e-6f, 1e-3f, 0.5f, 1.f, 0.f}) {
        for (float eta : {0.f, 1e-4f, 0.2f, 0.999f, 1.f, 1.0001f, 4.f, 100.f}) {
            for (float k : {0.f, 1e-4f, 1.f, 3.f, 10.f}) {
                float F = fresnelConductor(c, eta, k);
                INFO("conductor cos = " << c << ", eta = " << eta << ", k = " << k << ": " << F);
                CHECK(std::isfinite(F));
                CHECK(F >= 0.f);
                CHECK(F <= 1.f);
            }
            if (eta > 0.f) {
                for (float sign : {1.f, -1.f}) {
                    float F = fresnelDielectric(sign * c, eta);
                    INFO("dielectric cos = " << sign * c << ", eta = " << eta << ": " << F);
                    CHECK(std::isfinite(F));
                    CHECK(F >= 0.f);
                    CHECK(F <= 1.f);
                }
            }
        }
    }
    // Grazing incidence reflects (almost) everything off any real interface.
    CHECK(fresnelConductor(1e-6f, 0.2f, 3.f) > 0.9999f);
    CHECK(fresnelConductor(1e-6f, 4.f, 10.f) > 0.9999f);
    CHECK(fresnelDielectric(1e-6f, 1.5f) > 0.9999f);
    // η ≈ 1 keeps its digits: F(normal) = (1e-4 / 2.0001)² = 2.4998e-9.
    CHECK(fresnelDielectric(1.f, 1.0001f) == Approx(2.49975e-9).epsilon(1e-3));
    CHECK(fresnelConductor(1.f, 1.0001f, 0.f) == Approx(2.49975e-9).epsilon(1e-3));
}

TEST_CASE("fresnel: reflection and refraction directions", "[fresnel]") {
    Vector3f wo = normalize(Vector3f(0.3f, -0.4f, 0.8f));
    Vector3f r = reflectLocal(wo);
    CHECK(r.x == -wo.x);
    CHECK(r.y == -wo.y);
    CHECK(r.z == wo.z);
    // Snell's law n1 sinθ1 = n2 sinθ2, the plane of incidence kept, sides swapped.
    for (float eta : {1.5f, 1.f / 1.5f, 2.42f}) {
        for (float sign : {1.f, -1.f}) {
            Vector3f wi = normalize(Vector3f(0.2f, 0.1f, sign * 0.9f));
            Vector3f wt(0.f);
            float etaRel = 0.f;
            REQUIRE(refractLocal(wi, eta, wt, etaRel));
            float n1 = sign > 0 ? 1.f : eta, n2 = sign > 0 ? eta : 1.f;
            float sinI = std::sqrt(wi.x * wi.x + wi.y * wi.y), sinT = std::sqrt(wt.x * wt.x + wt.y * wt.y);
            CHECK(n1 * sinI == Approx(n2 * sinT).epsilon(1e-5));
            CHECK(length(wt) == Approx(1.f).epsilon(1e-5));
            CHECK(wt.z * wi.z < 0.f);
            CHECK(wt.x * wi.y == Approx(wt.y * wi.x).margin(1e-6));  // same plane of incidence
            CHECK(wt.x * wi.x < 0.f);                                  // continues across the normal
            CHECK(etaRel == Approx(n2 / n1));
        }
    }
}

TEST_CASE("fresnel: the inline principal square root is std::sqrt's, without cancellation", "[fresnel]") {
    // Both branches (a >= 0, a < 0), signed zeros, and parts 20 orders of magnitude apart
    // (where the cancelling form sqrt((|z| + a) / 2) with a < 0 would lose every digit).
    const double parts[] = {0.0, -0.0, 1e-10, -1e-10, 0.3, -0.3, 1.0, -1.0, 7.5, -7.5, 1e10, -1e10};
    for (double a : parts)
        for (double b : parts) {
            std::complex<double> ours = principalSqrt(a, b), ref = std::sqrt(std::complex<double>(a, b));
            INFO("sqrt(" << a << " + " << b << "i): " << ours << " vs " << ref);
            CHECK(ours.real() >= 0.0);
            CHECK(std::abs(ours - ref) <= 1e-14 * std::max(1e-300, std::abs(ref)));
        }
}
