#pragma once
// What a component accepts: typed parameters with defaults, units, ranges and a
// one-line doc each, plus the nested components it takes. The schema drives
// validation, `effigi info`, docs/components.md and the conformance runner.
#include "effigi/core/properties.hpp"

#include <optional>
#include <string>
#include <vector>

namespace effigi {

enum class ParamType { Bool, Int, Float, String, Point, Vector, Transform, Spectrum, Texture, Component };

const char* paramTypeName(ParamType t);

struct ParamSpec {
    std::string name;
    ParamType type = ParamType::Float;
    std::optional<PropertyValue> defaultValue;  // none and !required: optional, no default
    std::string doc;
    std::string unit;
    std::optional<double> min, max;
    std::vector<std::string> choices;   // String: allowed values
    SpectrumKind spectrumKind = SpectrumKind::Reflectance;
    std::string componentTag;           // Component, Texture: the accepted tag ("texture" if empty)
    bool required = false;
    bool multiple = false;              // Component: any number of unnamed children
    bool acceptsName = false;           // Float/Spectrum: a <string> (a named value) is accepted too
    bool ignored = false;               // accepted for Mitsuba compatibility, not used (said at -v)

    ParamSpec& range(double lo, double hi) { min = lo; max = hi; return *this; }
    ParamSpec& atLeast(double lo) { min = lo; return *this; }
    ParamSpec& withUnit(std::string u) { unit = std::move(u); return *this; }
    ParamSpec& oneOf(std::vector<std::string> c) { choices = std::move(c); return *this; }
    ParamSpec& isRequired() { required = true; return *this; }
    /// Also accept a string naming the value (Mitsuba's int_ior="bk7"); the component resolves it.
    ParamSpec& orName() { acceptsName = true; return *this; }
    /// Accepted because Mitsuba's plugin of the same name takes it, but not used by this
    /// component: validation says so once at -v instead of failing.
    ParamSpec& isIgnored() { ignored = true; return *this; }
};

/// A named parameter set the conformance runner instantiates (ordinary or extreme).
struct ConformanceConfig {
    std::string name;
    std::vector<std::pair<std::string, PropertyValue>> params;
};

/// A departure of the published model a component implements from the ideal a
/// conformance check holds it to, declared by the component with the reason: e.g. the
/// Oren–Nayar fit's albedo reaching 1.05 at ρ = 1. The check then holds the component to
/// `bound` instead, and reports the departure from the ideal as information.
struct ConformanceAllowance {
    std::string check;  ///< the check's name ("energy")
    double bound = 0.0;
    std::string reason;
};

class Schema {
public:
    Schema() = default;
    Schema(std::string tag, std::string name, std::string doc)
        : m_tag(std::move(tag)), m_name(std::move(name)), m_doc(std::move(doc)) {}

    const std::string& tag() const { return m_tag; }
    const std::string& name() const { return m_name; }
    const std::string& doc() const { return m_doc; }
    const std::string& reference() const { return m_reference; }
    const std::vector<ParamSpec>& params() const { return m_params; }
    const std::vector<ConformanceConfig>& conformance() const { return m_configs; }
    const ParamSpec* find(const std::string& name) const;

    Schema& cite(std::string ref) { m_reference = std::move(ref); return *this; }

    ParamSpec& boolean(const std::string& name, bool def, std::string doc);
    ParamSpec& integer(const std::string& name, std::int64_t def, std::string doc);
    ParamSpec& real(const std::string& name, double def, std::string doc);
    ParamSpec& string(const std::string& name, std::string def, std::string doc);
    ParamSpec& point(const std::string& name, Point3f def, std::string doc);
    ParamSpec& vector(const std::string& name, Vector3f def, std::string doc);
    /// A transform, identity unless given.
    ParamSpec& transform(const std::string& name, std::string doc);
    /// Spectral value (float, rgb or spectrum), no texture.
    ParamSpec& spectrum(const std::string& name, float def, SpectrumKind kind, std::string doc);
    /// Spectral value or nested texture.
    ParamSpec& texture(const std::string& name, float def, SpectrumKind kind, std::string doc);
    /// Spectral value or nested <volume> (a 3-D texture: a heterogeneous medium's
    /// sigma_t and albedo); type Texture with componentTag "volume".
    ParamSpec& volume(const std::string& name, float def, SpectrumKind kind, std::string doc);
    /// A parameter without a default that may be omitted (e.g. an optional nested part).
    ParamSpec& optional(const std::string& name, ParamType type, std::string doc);
    /// A nested component; `name` is also the name unnamed children of this tag get.
    ParamSpec& child(const std::string& tag, const std::string& name, std::string doc);
    /// Any number of unnamed nested components of one tag.
    ParamSpec& children(const std::string& tag, std::string doc);
    /// A parameter Mitsuba's plugin of the same name accepts and this one ignores (any
    /// value type is accepted); `doc` says why it is ignored.
    ParamSpec& ignored(const std::string& name, std::string doc);

    Schema& addConformance(ConformanceConfig c) { m_configs.push_back(std::move(c)); return *this; }
    Schema& allow(ConformanceAllowance a) { m_allowances.push_back(std::move(a)); return *this; }
    const std::vector<ConformanceAllowance>& allowances() const { return m_allowances; }
    /// The allowance declared for a check, if any.
    const ConformanceAllowance* allowance(const std::string& check) const {
        for (const ConformanceAllowance& a : m_allowances)
            if (a.check == check) return &a;
        return nullptr;
    }

    /// Check user properties against the schema and add defaults: unknown names and
    /// wrong types are errors naming file:line and the closest known parameter.
    void validate(Properties& props) const;

private:
    ParamSpec& add(ParamSpec p);

    std::string m_tag, m_name, m_doc, m_reference;
    std::vector<ParamSpec> m_params;
    std::vector<ConformanceConfig> m_configs;
    std::vector<ConformanceAllowance> m_allowances;
};

} // namespace effigi
