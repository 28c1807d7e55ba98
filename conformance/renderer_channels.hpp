#pragma once
// The renderer suite's checks of channels other than colour (conformance/renderer_channels.cpp).
#include "conformance/conformance.hpp"

namespace effigi::conform {

/// On the sky plane (renderer_scenes.hpp), the channels a renderer writes besides colour:
/// AOVs of known surfaces, moments, nested renderers' colour; `colour` false (a wrapper
/// without nested renderers): the colour image must be black. Nothing for renderers that
/// write colour only.
void checkChannels(Target& t, bool colour);

} // namespace effigi::conform
