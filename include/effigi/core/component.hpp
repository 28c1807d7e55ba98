#pragma once
// The root of the component model (COM-like, after EFFIGI): every plugin object is
// an IComponent that answers query(InterfaceId) with one of its interfaces or null.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace effigi {

using InterfaceId = std::uint64_t;

/// 64-bit FNV-1a of a string: stable across builds, platforms and modules.
constexpr std::uint64_t fnv1a(std::string_view text) {
    std::uint64_t h = 1469598103934665603ull;
    for (char c : text) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    return h;
}

/// The interface id is the hash of its name.
constexpr InterfaceId interfaceId(std::string_view name) { return fnv1a(name); }

/// Shared ownership of components. Modules are never unloaded, so vtables outlive objects.
template <typename T> using Ref = std::shared_ptr<T>;

class IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IComponent");
    static constexpr const char* Tag = "component";

    virtual ~IComponent() = default;

    /// QueryInterface: a pointer to the requested interface of this object, or null.
    virtual void* query(InterfaceId iid) = 0;

    /// Typed QueryInterface, usable unqualified inside components (the virtual member
    /// above would otherwise hide the namespace-level effigi::query helpers).
    template <typename I> static Ref<I> query(const Ref<IComponent>& obj);
    template <typename I> static I* query(IComponent* obj);

    /// "tag/name" of the factory that made this object (set by the registry).
    const std::string& typeName() const { return m_typeName; }
    /// The XML id, if the object was declared with one.
    const std::string& id() const { return m_id; }

    void setIdentity(std::string typeName, std::string id) {
        m_typeName = std::move(typeName);
        m_id = std::move(id);
    }

private:
    std::string m_typeName;
    std::string m_id;
};

/// Implements query() for a component that realises the interfaces Is...
/// Interfaces inherit IComponent virtually, so one object has one IComponent.
template <typename... Is> class Implements : public Is... {
public:
    using IComponent::query;  // keep the typed helpers visible next to the override
    void* query(InterfaceId iid) override {
        void* found = nullptr;
        (void)((iid == Is::IID ? (found = static_cast<Is*>(this), true) : false) || ...);
        if (!found && iid == IComponent::IID) found = static_cast<IComponent*>(this);
        return found;
    }
};

/// Typed QueryInterface on a shared object; shares ownership with it.
template <typename I> Ref<I> query(const Ref<IComponent>& obj) {
    if (!obj) return nullptr;
    void* p = obj->query(I::IID);
    return p ? Ref<I>(obj, static_cast<I*>(p)) : nullptr;
}

template <typename I> I* query(IComponent* obj) {
    return obj ? static_cast<I*>(obj->query(I::IID)) : nullptr;
}

template <typename I> Ref<I> IComponent::query(const Ref<IComponent>& obj) { return effigi::query<I>(obj); }
template <typename I> I* IComponent::query(IComponent* obj) { return effigi::query<I>(obj); }

} // namespace effigi
