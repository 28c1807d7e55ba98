#pragma once
// ITextureResolution — an optional second interface of textures backed by an image:
// the image's size in texels (Mitsuba's Texture::resolution()). The projector emitter
// takes its aspect ratio from it; a texture that does not implement it counts as 1 × 1,
// as constant textures do in Mitsuba. A texture opts in with
//   class BitmapTexture : public Implements<ITexture, ITextureResolution> { ... }
#include "effigi/core/component.hpp"
#include "effigi/math/vector.hpp"

namespace effigi {

class ITextureResolution : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ITextureResolution");
    static constexpr const char* Tag = "texture";

    /// Width and height in texels (both ≥ 1).
    virtual Vector2i resolution() const = 0;
};

} // namespace effigi
