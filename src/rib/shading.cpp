// RIB shading requests -> effigi BSDF and emitter elements.
//
// Surfaces (RenderMan Interface 3.2, appendix A, with their defaults), Cs = Color:
//   matte   Ka=1 Kd=1                     -> diffuse, reflectance Kd·Cs
//   plastic Ka=1 Kd=.5 Ks=.5 roughness=.1 specularcolor=1
//                                         -> roughplastic (Beckmann), diffuse_reflectance Kd·Cs,
//                                            specular_reflectance Ks·specularcolor
//   metal   Ka=1 Ks=1 roughness=.1        -> roughconductor (Beckmann, a 100 % mirror),
//                                            specular_reflectance Ks·Cs
// RenderMan's specular() raises N·H to 1/roughness (RI 3.2, §15.9: a Blinn lobe of
// exponent n = 1/roughness); the Beckmann roughness with the same highlight width is
// α = sqrt(2 / (n + 2)) (Walter et al. 2007, §5.2). Below α = 1e-3 the smooth plastic /
// conductor is used. Reflectances are clamped to [0, 1] (a warning says so). Ka has no
// counterpart: an ambientlight is real light here, so ambient() is what every surface
// receives from it. The shaders turn the normal toward the viewer (faceforward), so
// every BSDF is wrapped in `twosided`; an Opacity below 1 wraps it in `mask` with the
// mean of the three opacities.
//
// Lights (RI 3.2, appendix A), Cl = intensity·lightcolor:
//   pointlight   from=(0,0,0)          -> point, intensity π·Cl at CTM·from
//   distantlight from=(0,0,0) to=(0,0,1) -> directional, irradiance π·Cl along CTM·(to − from)
//   ambientlight                       -> constant environment, radiance Cl
// RenderMan's diffuse() sums Cl·(N·L) without the 1/π of a Lambertian BRDF, so the lights
// are π times brighter here: a matte surface then looks as bright as RenderMan shows it.
// The constant environment is also seen behind the scene (RenderMan's background stays
// black). Lights are global: RenderMan's per-attribute light list is not modelled.
#include "state.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace effigi::rib {

namespace {

constexpr double Pi = std::numbers::pi;  // in double, as the transformations are kept

/// A colour from Color / Opacity: 3 numbers (bare or bracketed), each in [lo, hi].
Vector3d colorArg(Args& a, double hi) {
    std::vector<double> v = a.numbers(3);
    a.end();
    for (double x : v)
        if (!(x >= 0.0 && x <= hi))
            a.fail("components must lie in [0, {}], got {} {} {}", hi == MaxNumber ? "1e38" : "1", v[0], v[1], v[2]);
    return {v[0], v[1], v[2]};
}

RGBValue rgb(Vector3d v) { return RGBValue{Vector3f(v)}; }

/// A reflectance for a [0, 1] parameter; larger values are clamped with a warning.
RGBValue reflectance(Vector3d v, const char* what, const SourceLocation& where) {
    Vector3d c = glm::clamp(v, 0.0, 1.0);
    if (c != v) log::warn("{}: {} ({}, {}, {}) clamped to [0, 1]", where.str(), what, v.x, v.y, v.z);
    return rgb(c);
}

double beckmannAlpha(double roughness) { return std::sqrt(2.0 / (1.0 / roughness + 2.0)); }

double nonNegative(Params& p, Args& a, const char* name, double def) {
    double v = p.real(name, def);
    if (!(v >= 0.0)) a.fail("parameter '{}' must be >= 0, got {}", name, v);
    return v;
}

Vector3d lightColor(Params& p, Args& a) {
    double intensity = nonNegative(p, a, "intensity", 1.0);
    Vector3d c = p.triple("lightcolor", Vector3d(1.0));
    if (!(c.x >= 0.0 && c.y >= 0.0 && c.z >= 0.0)) a.fail("parameter 'lightcolor' must be >= 0");
    return intensity * c;
}

Vector3d toWorld(const glm::dmat4& m, Vector3d v, double w) { return Vector3d(m * glm::dvec4(v, w)); }

} // namespace

void reqColor(State& s, Args& a) { s.attr.material.color = colorArg(a, MaxNumber); }
void reqOpacity(State& s, Args& a) { s.attr.material.opacity = colorArg(a, 1.0); }

void reqSurface(State& s, Args& a) {
    Surface sf;
    sf.type = a.string("shader name");
    sf.where = a.where();
    a.setLabel(fmt::format("Surface \"{}\"", excerpt(sf.type)));
    const bool matte = sf.type == "matte", plastic = sf.type == "plastic", metal = sf.type == "metal";
    if (!matte && !plastic && !metal)
        a.fail("surface shader '{}' is not supported (matte, plastic and metal are)", excerpt(sf.type));
    Params p = a.params();
    sf.ka = nonNegative(p, a, "Ka", 1.0);
    sf.kd = matte ? nonNegative(p, a, "Kd", 1.0) : plastic ? nonNegative(p, a, "Kd", 0.5) : 0.0;
    sf.ks = plastic ? nonNegative(p, a, "Ks", 0.5) : metal ? nonNegative(p, a, "Ks", 1.0) : 0.0;
    if (!matte) {
        sf.roughness = nonNegative(p, a, "roughness", 0.1);
        if (plastic) sf.specularColor = p.triple("specularcolor", Vector3d(1.0));
    }
    p.finish();
    s.attr.material.surface = sf;
}

void reqLightSource(State& s, Args& a) {
    const std::string name = a.string("shader name");
    a.setLabel(fmt::format("LightSource \"{}\"", excerpt(name)));
    const bool point = name == "pointlight", distant = name == "distantlight", ambient = name == "ambientlight";
    if (!point && !distant && !ambient)
        a.fail("light shader '{}' is not supported (pointlight, distantlight and ambientlight are)", excerpt(name));
    a.handle();
    Params p = a.params();
    const Vector3d cl = lightColor(p, a);
    if (!(Pi * std::max({cl.x, cl.y, cl.z}) <= 1e30)) a.fail("intensity · lightcolor is beyond 1e30");
    std::unique_ptr<xml::Node> n;
    if (point) {
        Vector3d from = toWorld(s.attr.ctm, p.triple("from", Vector3d(0.0)), 1.0);
        if (!(std::max({std::abs(from.x), std::abs(from.y), std::abs(from.z)}) <= MaxNumber))
            a.fail("the light's position is out of range (beyond ±1e38)");
        n = makeNode("emitter", "point", a.where());
        n->props.set("position", PointValue{Point3f(from)}, a.where());
        n->props.set("intensity", rgb(Pi * cl), a.where());
    } else if (distant) {
        Vector3d from = p.triple("from", Vector3d(0.0)), to = p.triple("to", Vector3d(0.0, 0.0, 1.0));
        Vector3d d = toWorld(s.attr.ctm, to - from, 0.0);
        double len = glm::length(d);
        if (!(len > 0.0) || !std::isfinite(len)) a.fail("'from' and 'to' must give a non-zero, finite direction");
        n = makeNode("emitter", "directional", a.where());
        n->props.set("direction", VectorValue{Vector3f(d / len)}, a.where());
        n->props.set("irradiance", rgb(Pi * cl), a.where());
    } else {
        n = makeNode("emitter", "constant", a.where());
        n->props.set("radiance", rgb(cl), a.where());
    }
    p.finish();
    s.scene.emitters.push_back(std::move(n));
}

std::unique_ptr<xml::Node> bsdfNode(const Material& m, const SourceLocation& where) {
    const Surface& sf = m.surface;
    std::unique_ptr<xml::Node> inner;
    const double alpha = beckmannAlpha(sf.roughness);
    const bool smooth = !(alpha >= 1e-3);
    if (sf.type == "plastic") {
        inner = makeNode("bsdf", smooth ? "plastic" : "roughplastic", where);
        inner->props.set("diffuse_reflectance", reflectance(sf.kd * m.color, "Kd·Cs", where), where);
        inner->props.set("specular_reflectance", reflectance(sf.ks * sf.specularColor, "Ks·specularcolor", where), where);
    } else if (sf.type == "metal") {
        inner = makeNode("bsdf", smooth ? "conductor" : "roughconductor", where);
        inner->props.set("specular_reflectance", reflectance(sf.ks * m.color, "Ks·Cs", where), where);
    } else {
        inner = makeNode("bsdf", "diffuse", where);
        inner->props.set("reflectance", reflectance(sf.kd * m.color, "Kd·Cs", where), where);
    }
    if (sf.type != "matte" && !smooth) {
        inner->props.set("distribution", std::string("beckmann"), where);
        inner->props.set("alpha", std::min(alpha, 4.0), where);
    }
    std::unique_ptr<xml::Node> outer = makeNode("bsdf", "twosided", where);
    outer->children.push_back(xml::Child{"", std::move(inner), "", where});
    const double opacity = (m.opacity.x + m.opacity.y + m.opacity.z) / 3.0;
    if (opacity >= 1.0) return outer;
    std::unique_ptr<xml::Node> mask = makeNode("bsdf", "mask", where);
    mask->props.set("opacity", opacity, where);
    mask->children.push_back(xml::Child{"", std::move(outer), "", where});
    return mask;
}

} // namespace effigi::rib
