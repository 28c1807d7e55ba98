#pragma once
// The named, typed parameters a component is created from (one XML element's
// children). Every entry remembers where it was written so errors can point at it.
#include "effigi/core/component.hpp"
#include "effigi/core/error.hpp"
#include "effigi/math/animated_transform.hpp"
#include "effigi/math/transform.hpp"
#include "effigi/spectral/spectrum.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace effigi {

class ITexture;

struct PointValue { Point3f v; };
struct VectorValue { Vector3f v; };
struct RGBValue { Vector3f v; };
/// A spectrum as written: tabulated (λ, value) pairs, a single constant, a blackbody,
/// or the name of a spectrum shipped with effigi (effigi/spectral/named.hpp).
struct SpectrumValue {
    std::vector<float> lambdas, values;  // empty lambdas + one value = constant
    float temperature = 0.f;             // > 0: blackbody at this temperature
    float scale = 1.f;
    std::string name;                    // non-empty: namedSpectrum(name), resolved on use
};
/// A nested component together with the XML tag it was declared with.
struct ComponentValue {
    std::string tag;
    Ref<IComponent> object;
};

using PropertyValue = std::variant<bool, std::int64_t, double, std::string, PointValue, VectorValue,
                                   RGBValue, SpectrumValue, Transform, ComponentValue, AnimatedTransform>;

/// Human-readable name of the type a PropertyValue holds ("float", "rgb", ...).
std::string propertyTypeName(const PropertyValue& v);

class Properties {
public:
    struct Entry {
        std::string name;
        PropertyValue value;
        SourceLocation where;
        bool fromDefault = false;  // filled in from the schema, not written by the user
    };

    Properties() = default;
    Properties(std::string tag, std::string type, SourceLocation where = {})
        : m_tag(std::move(tag)), m_type(std::move(type)), m_where(std::move(where)) {}

    const std::string& tag() const { return m_tag; }
    const std::string& type() const { return m_type; }
    const std::string& id() const { return m_id; }
    void setId(std::string id) { m_id = std::move(id); }
    const SourceLocation& where() const { return m_where; }
    /// "bsdf 'diffuse'": how errors name the element.
    std::string describe() const;

    /// Add or replace a value; a name given twice by the user is an error.
    void set(const std::string& name, PropertyValue value, SourceLocation where = {}, bool fromDefault = false);
    bool has(const std::string& name) const { return find(name) != nullptr; }
    void remove(const std::string& name);
    const Entry* find(const std::string& name) const;
    const std::vector<Entry>& entries() const { return m_entries; }
    /// Location of an entry, or of the element when the entry is absent.
    const SourceLocation& whereOf(const std::string& name) const;

    bool getBool(const std::string& name) const;
    std::int64_t getInt(const std::string& name) const;
    float getFloat(const std::string& name) const;
    const std::string& getString(const std::string& name) const;
    /// A file name; relative names resolve against the directory of the scene file the
    /// property was written in (or the working directory when it has no file).
    std::filesystem::path getPath(const std::string& name) const;
    Point3f getPoint(const std::string& name) const;
    Vector3f getVector(const std::string& name) const;
    /// A transform; an <animation> that moves is an error naming the parameter (only
    /// components that call getAnimatedTransform move).
    Transform getTransform(const std::string& name) const;
    /// A transform or an <animation> (a still transform is an animation of one key).
    AnimatedTransform getAnimatedTransform(const std::string& name) const;
    /// A spectral parameter as a value (float, rgb or spectrum); RGB upsampled by kind.
    Spectrum getSpectrum(const std::string& name, SpectrumKind kind) const;
    /// A spectral parameter that may also be a nested texture; constants are wrapped.
    Ref<ITexture> getTexture(const std::string& name, SpectrumKind kind) const;
    /// A nested component by parameter name, or null.
    Ref<IComponent> getComponent(const std::string& name) const;
    /// Every nested component declared with the given tag, in file order.
    std::vector<Ref<IComponent>> components(const std::string& tag) const;

    /// Typed nested component by name: null if absent, error if of another interface.
    template <typename I> Ref<I> get(const std::string& name) const {
        Ref<IComponent> c = getComponent(name);
        if (!c) return nullptr;
        Ref<I> r = effigi::query<I>(c);
        if (!r) failAt(whereOf(name), "{}: '{}' is not a {}", describe(), name, I::Tag);
        return r;
    }

private:
    const Entry& require(const std::string& name) const;
    [[noreturn]] void typeError(const Entry& e, const char* expected) const;

    std::string m_tag, m_type, m_id;
    SourceLocation m_where;
    std::vector<Entry> m_entries;
};

} // namespace effigi
