#pragma once
#include <string>
#include <vector>

namespace effigi::app {

int render(const std::vector<std::string>& args);
/// One render; `joinMpi`: under mpirun, share its samples with the other ranks (render.cpp).
int renderOne(const std::vector<std::string>& args, bool joinMpi);
/// --frames A:B: a sequence, one render per frame (render_frames.cpp).
bool hasFramesOption(const std::vector<std::string>& args);
int renderFrames(const std::vector<std::string>& args);
int list(const std::vector<std::string>& args);
int info(const std::vector<std::string>& args);
int converge(const std::vector<std::string>& args);
/// Spectral EXR -> RGB EXR or PNG (convert.cpp).
int convert(const std::vector<std::string>& args);

} // namespace effigi::app
