#include "effigi/core/properties.hpp"

#include "effigi/core/input.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/constant_texture.hpp"
#include "effigi/spectral/named.hpp"

#include <algorithm>

namespace effigi {

std::string propertyTypeName(const PropertyValue& v) {
    static const char* names[] = {"boolean", "integer", "float", "string", "point",
                                  "vector", "rgb", "spectrum", "transform", "object", "animation"};
    if (auto* c = std::get_if<ComponentValue>(&v)) return c->tag.empty() ? "object" : c->tag;
    return names[v.index()];
}

std::string Properties::describe() const {
    if (m_type.empty()) return m_tag;
    return fmt::format("{} '{}'", m_tag, excerpt(m_type));  // the type comes from the scene file
}

void Properties::set(const std::string& name, PropertyValue value, SourceLocation where, bool fromDefault) {
    if (!name.empty()) {
        for (auto& e : m_entries) {
            if (e.name != name) continue;
            if (!e.fromDefault && !fromDefault)
                failAt(where, "{}: parameter '{}' given twice (first at line {})", describe(), name, e.where.line);
            e = Entry{name, std::move(value), std::move(where), fromDefault};
            return;
        }
    }
    m_entries.push_back(Entry{name, std::move(value), std::move(where), fromDefault});
}

void Properties::remove(const std::string& name) {
    std::erase_if(m_entries, [&](const Entry& e) { return e.name == name; });
}

const Properties::Entry* Properties::find(const std::string& name) const {
    for (const auto& e : m_entries)
        if (e.name == name) return &e;
    return nullptr;
}

const SourceLocation& Properties::whereOf(const std::string& name) const {
    const Entry* e = find(name);
    return e && e->where.known() ? e->where : m_where;
}

const Properties::Entry& Properties::require(const std::string& name) const {
    const Entry* e = find(name);
    if (!e) failAt(m_where, "{}: missing parameter '{}'", describe(), name);
    return *e;
}

void Properties::typeError(const Entry& e, const char* expected) const {
    failAt(e.where.known() ? e.where : m_where, "{}: parameter '{}' must be {}, got {}", describe(), e.name,
           expected, propertyTypeName(e.value));
}

bool Properties::getBool(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* b = std::get_if<bool>(&e.value)) return *b;
    typeError(e, "a boolean");
}

std::int64_t Properties::getInt(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* i = std::get_if<std::int64_t>(&e.value)) return *i;
    typeError(e, "an integer");
}

float Properties::getFloat(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* d = std::get_if<double>(&e.value)) return float(*d);
    if (auto* i = std::get_if<std::int64_t>(&e.value)) return float(*i);
    typeError(e, "a float");
}

const std::string& Properties::getString(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* s = std::get_if<std::string>(&e.value)) return *s;
    typeError(e, "a string");
}

std::filesystem::path Properties::getPath(const std::string& name) const {
    std::filesystem::path p = getString(name);
    if (p.is_relative()) {
        const SourceLocation& w = whereOf(name);
        if (w.known()) p = std::filesystem::path(w.file).parent_path() / p;
    }
    return p;
}

Point3f Properties::getPoint(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* p = std::get_if<PointValue>(&e.value)) return p->v;
    if (auto* v = std::get_if<VectorValue>(&e.value)) return v->v;
    typeError(e, "a point");
}

Vector3f Properties::getVector(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<VectorValue>(&e.value)) return v->v;
    if (auto* p = std::get_if<PointValue>(&e.value)) return p->v;
    typeError(e, "a vector");
}

Transform Properties::getTransform(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* t = std::get_if<Transform>(&e.value)) return *t;
    if (auto* a = std::get_if<AnimatedTransform>(&e.value)) {
        if (!a->isAnimated()) return a->first();
        failAt(e.where, "{}: '{}' is an <animation>, but {} does not move (animated are shapes and cameras)",
               describe(), name, describe());
    }
    typeError(e, "a transform");
}

AnimatedTransform Properties::getAnimatedTransform(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* a = std::get_if<AnimatedTransform>(&e.value)) return *a;
    return AnimatedTransform(getTransform(name));
}

Spectrum Properties::getSpectrum(const std::string& name, SpectrumKind kind) const {
    const Entry& e = require(name);
    // A bare number given for an emission is a grey of the colour space, i.e. a scaled
    // D65, as Mitsuba 3's spectral variants read <float> radiance/intensity/irradiance
    // (a <spectrum value="v"/> stays flat, as there).
    auto number = [&](float v) {
        return kind == SpectrumKind::Illuminant ? Spectrum::fromRGB(Vector3f(v), kind) : Spectrum(v);
    };
    if (auto* d = std::get_if<double>(&e.value)) return number(float(*d));
    if (auto* i = std::get_if<std::int64_t>(&e.value)) return number(float(*i));
    if (auto* c = std::get_if<RGBValue>(&e.value)) return Spectrum::fromRGB(c->v, kind);
    if (auto* s = std::get_if<SpectrumValue>(&e.value)) {
        Spectrum r;
        if (!s->name.empty()) {
            try {
                r = namedSpectrum(s->name);
            } catch (const Error& err) {
                failAt(e.where.known() ? e.where : m_where, "{}: parameter '{}': {}", describe(), name, err.what());
            }
        } else if (s->temperature > 0.f)
            r = Spectrum::blackbody(s->temperature);
        else if (s->lambdas.empty() && s->values.size() == 1)
            r = Spectrum(s->values[0]);
        else
            r = Spectrum::piecewiseLinear(s->lambdas, s->values);
        return r.scaled(s->scale);
    }
    typeError(e, "a spectrum (float, rgb or spectrum)");
}

Ref<ITexture> Properties::getTexture(const std::string& name, SpectrumKind kind) const {
    const Entry& e = require(name);
    if (auto* c = std::get_if<ComponentValue>(&e.value)) {
        Ref<ITexture> t = effigi::query<ITexture>(c->object);
        if (!t) typeError(e, "a texture or spectrum");
        return t;
    }
    return std::make_shared<ConstantTexture>(getSpectrum(name, kind));
}

Ref<IComponent> Properties::getComponent(const std::string& name) const {
    const Entry* e = find(name);
    if (!e) return nullptr;
    if (auto* c = std::get_if<ComponentValue>(&e->value)) return c->object;
    typeError(*e, "a nested object");
}

std::vector<Ref<IComponent>> Properties::components(const std::string& tag) const {
    std::vector<Ref<IComponent>> out;
    for (const auto& e : m_entries)
        if (auto* c = std::get_if<ComponentValue>(&e.value); c && c->tag == tag) out.push_back(c->object);
    return out;
}

} // namespace effigi
