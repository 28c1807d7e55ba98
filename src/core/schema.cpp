#include "effigi/core/schema.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"

#include <mutex>
#include <set>

#include <cmath>

namespace effigi {

const char* paramTypeName(ParamType t) {
    switch (t) {
    case ParamType::Bool: return "boolean";
    case ParamType::Int: return "integer";
    case ParamType::Float: return "float";
    case ParamType::String: return "string";
    case ParamType::Point: return "point";
    case ParamType::Vector: return "vector";
    case ParamType::Transform: return "transform";
    case ParamType::Spectrum: return "spectrum";
    case ParamType::Texture: return "texture";
    case ParamType::Component: return "object";
    }
    return "?";
}

ParamSpec& Schema::add(ParamSpec p) {
    if (find(p.name)) fail("schema of {} '{}' declares '{}' twice", m_tag, m_name, p.name);
    m_params.push_back(std::move(p));
    return m_params.back();
}

const ParamSpec* Schema::find(const std::string& name) const {
    for (const auto& p : m_params)
        if (p.name == name) return &p;
    return nullptr;
}

namespace {
ParamSpec makeSpec(const std::string& name, ParamType type, std::optional<PropertyValue> def, std::string doc) {
    ParamSpec p;
    p.name = name;
    p.type = type;
    p.defaultValue = std::move(def);
    p.doc = std::move(doc);
    return p;
}
} // namespace

ParamSpec& Schema::boolean(const std::string& name, bool def, std::string doc) {
    return add(makeSpec(name, ParamType::Bool, def, std::move(doc)));
}
ParamSpec& Schema::integer(const std::string& name, std::int64_t def, std::string doc) {
    return add(makeSpec(name, ParamType::Int, def, std::move(doc)));
}
ParamSpec& Schema::real(const std::string& name, double def, std::string doc) {
    return add(makeSpec(name, ParamType::Float, def, std::move(doc)));
}
ParamSpec& Schema::string(const std::string& name, std::string def, std::string doc) {
    return add(makeSpec(name, ParamType::String, std::move(def), std::move(doc)));
}
ParamSpec& Schema::point(const std::string& name, Point3f def, std::string doc) {
    return add(makeSpec(name, ParamType::Point, PointValue{def}, std::move(doc)));
}
ParamSpec& Schema::vector(const std::string& name, Vector3f def, std::string doc) {
    return add(makeSpec(name, ParamType::Vector, VectorValue{def}, std::move(doc)));
}
ParamSpec& Schema::transform(const std::string& name, std::string doc) {
    return add(makeSpec(name, ParamType::Transform, Transform(), std::move(doc)));
}
ParamSpec& Schema::spectrum(const std::string& name, float def, SpectrumKind kind, std::string doc) {
    ParamSpec& p = add(makeSpec(name, ParamType::Spectrum, double(def), std::move(doc)));
    p.spectrumKind = kind;
    return p;
}
ParamSpec& Schema::texture(const std::string& name, float def, SpectrumKind kind, std::string doc) {
    ParamSpec& p = add(makeSpec(name, ParamType::Texture, double(def), std::move(doc)));
    p.spectrumKind = kind;
    p.componentTag = "texture";
    return p;
}
ParamSpec& Schema::volume(const std::string& name, float def, SpectrumKind kind, std::string doc) {
    ParamSpec& p = texture(name, def, kind, std::move(doc));
    p.componentTag = "volume";
    return p;
}
ParamSpec& Schema::optional(const std::string& name, ParamType type, std::string doc) {
    return add(makeSpec(name, type, std::nullopt, std::move(doc)));
}
ParamSpec& Schema::child(const std::string& tag, const std::string& name, std::string doc) {
    ParamSpec& p = add(makeSpec(name, ParamType::Component, std::nullopt, std::move(doc)));
    p.componentTag = tag;
    return p;
}
ParamSpec& Schema::children(const std::string& tag, std::string doc) {
    ParamSpec& p = add(makeSpec(tag + "[]", ParamType::Component, std::nullopt, std::move(doc)));
    p.componentTag = tag;
    p.multiple = true;
    return p;
}

ParamSpec& Schema::ignored(const std::string& name, std::string doc) {
    ParamSpec& p = add(makeSpec(name, ParamType::String, std::nullopt, std::move(doc)));
    p.ignored = true;
    return p;
}

namespace {

bool accepts(const ParamSpec& spec, const PropertyValue& v) {
    auto is = [&](auto* tag) { return std::holds_alternative<std::remove_pointer_t<decltype(tag)>>(v); };
    if (spec.acceptsName && is((std::string*)nullptr)) return true;
    switch (spec.type) {
    case ParamType::Bool: return is((bool*)nullptr);
    case ParamType::Int: return is((std::int64_t*)nullptr);
    case ParamType::Float: return is((double*)nullptr) || is((std::int64_t*)nullptr);
    case ParamType::String: return is((std::string*)nullptr);
    case ParamType::Point:
    case ParamType::Vector: return is((PointValue*)nullptr) || is((VectorValue*)nullptr);
    case ParamType::Transform: return is((Transform*)nullptr) || is((AnimatedTransform*)nullptr);
    case ParamType::Texture:
        if (auto* c = std::get_if<ComponentValue>(&v))
            return c->tag == (spec.componentTag.empty() ? std::string("texture") : spec.componentTag);
        [[fallthrough]];
    case ParamType::Spectrum:
        return is((double*)nullptr) || is((std::int64_t*)nullptr) || is((RGBValue*)nullptr) ||
               is((SpectrumValue*)nullptr);
    case ParamType::Component:
        if (auto* c = std::get_if<ComponentValue>(&v)) return c->tag == spec.componentTag;
        return false;
    }
    return false;
}

std::string expectedText(const ParamSpec& spec) {
    if (spec.acceptsName) {
        ParamSpec plain = spec;
        plain.acceptsName = false;
        return expectedText(plain) + " or a name";
    }
    switch (spec.type) {
    case ParamType::Float: return "a float";
    case ParamType::Int: return "an integer";
    case ParamType::Bool: return "a boolean";
    case ParamType::String: return "a string";
    case ParamType::Point: return "a point";
    case ParamType::Vector: return "a vector";
    case ParamType::Transform: return "a transform";
    case ParamType::Spectrum: return "a float, rgb or spectrum";
    case ParamType::Texture:
        return "a float, rgb, spectrum or " + (spec.componentTag.empty() ? std::string("texture") : spec.componentTag);
    case ParamType::Component: return "a nested " + spec.componentTag;
    }
    return "?";
}

void checkRange(const ParamSpec& spec, const Properties::Entry& e, const Properties& props) {
    double v;
    if (auto* d = std::get_if<double>(&e.value))
        v = *d;
    else if (auto* i = std::get_if<std::int64_t>(&e.value))
        v = double(*i);
    else
        return;
    if (!std::isfinite(v)) failAt(e.where, "{}: parameter '{}' is not a finite number", props.describe(), e.name);
    bool low = spec.min && v < *spec.min, high = spec.max && v > *spec.max;
    if (low || high) {
        std::string range = spec.min && spec.max ? fmt::format("[{}, {}]", *spec.min, *spec.max)
                            : spec.min           ? fmt::format(">= {}", *spec.min)
                                                 : fmt::format("<= {}", *spec.max);
        failAt(e.where, "{}: parameter '{}' = {} is out of range {}", props.describe(), e.name, v, range);
    }
}

} // namespace

void Schema::validate(Properties& props) const {
    std::vector<std::string> names;
    for (const auto& p : m_params)
        if (!p.multiple) names.push_back(p.name);

    // Work on a copy of the entries: unnamed children get renamed into their slot.
    std::vector<Properties::Entry> entries = props.entries();
    for (auto& e : entries) {
        if (e.fromDefault) continue;
        if (e.name.empty()) {
            auto* c = std::get_if<ComponentValue>(&e.value);
            if (!c) failAt(e.where, "{}: a value without a name", props.describe());
            const ParamSpec* slot = nullptr;
            for (const auto& p : m_params) {
                if (p.type != ParamType::Component) continue;
                if (p.componentTag != c->tag) continue;
                if (p.multiple) { slot = &p; break; }
                bool taken = std::any_of(entries.begin(), entries.end(), [&](auto& o) { return o.name == p.name; });
                if (!taken) { slot = &p; break; }
            }
            if (!slot) {
                std::vector<std::string> tags;
                for (const auto& p : m_params)
                    if (p.type == ParamType::Component) tags.push_back(p.componentTag);
                failAt(e.where, "{} does not accept {} nested {}{}", props.describe(),
                       tags.empty() ? "a" : "another", c->tag,
                       tags.empty() ? "" : fmt::format(" (accepts: {})", fmt::join(tags, ", ")));
            }
            if (!slot->multiple) e.name = slot->name;
            continue;
        }
        const ParamSpec* spec = find(e.name);
        // A nested object whose name is no parameter joins a children(tag) list of its tag
        // under that name: Mitsuba lets such children (bumpmap's height texture) carry any name.
        if (auto* c = std::get_if<ComponentValue>(&e.value); c && !spec) {
            bool listed = std::any_of(m_params.begin(), m_params.end(), [&](const ParamSpec& p) {
                return p.multiple && p.type == ParamType::Component && p.componentTag == c->tag;
            });
            if (listed) continue;
        }
        if (!spec || spec->multiple) {
            std::string hint = didYouMean(e.name, names);
            failAt(e.where, "{} has no parameter '{}'{}", props.describe(), excerpt(e.name),
                   hint.empty() ? fmt::format(" (parameters: {})", fmt::join(names, ", "))
                                : fmt::format(" (did you mean '{}'?)", hint));
        }
        if (spec->ignored) {
            // Mitsuba's plugin takes it; this one does not use it. Said once per
            // component and parameter, at -v.
            static std::mutex mutex;
            static std::set<std::string> said;
            std::string key = props.tag() + "/" + props.type() + "/" + e.name;
            std::lock_guard lock(mutex);
            if (said.insert(key).second)
                log::info("{}: {}: parameter '{}' accepted but ignored ({})", e.where.str(), props.describe(), e.name,
                          spec->doc);
            continue;
        }
        if (!accepts(*spec, e.value))
            failAt(e.where, "{}: parameter '{}' must be {}, got {}", props.describe(), e.name, expectedText(*spec),
                   propertyTypeName(e.value));
        checkRange(*spec, e, props);
        if (!spec->choices.empty()) {
            const auto& s = std::get<std::string>(e.value);
            if (std::find(spec->choices.begin(), spec->choices.end(), s) == spec->choices.end()) {
                std::string hint = didYouMean(s, spec->choices);
                failAt(e.where, "{}: parameter '{}' = '{}' is not one of {}{}", props.describe(), e.name, excerpt(s),
                       fmt::join(spec->choices, ", "), hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint));
            }
        }
    }

    Properties out(props.tag(), props.type(), props.where());
    out.setId(props.id());
    for (auto& e : entries) out.set(e.name, std::move(e.value), e.where, e.fromDefault);
    for (const auto& p : m_params) {
        if (p.multiple || out.has(p.name)) continue;
        if (p.defaultValue)
            out.set(p.name, *p.defaultValue, props.where(), true);
        else if (p.required)
            failAt(props.where(), "{}: missing required parameter '{}' ({})", props.describe(), p.name, p.doc);
    }
    props = std::move(out);
}

} // namespace effigi
