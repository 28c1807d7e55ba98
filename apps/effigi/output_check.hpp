#pragma once
// Output paths are checked before a render starts, so that a path that cannot be written
// fails in a second rather than after an hour of rendering.
#include <filesystem>

namespace effigi::app {

/// Fails with one line, "cannot write <path>: <reason>", unless a file can be written at
/// `path`: an existing folder there, or a file standing where a folder should be, is
/// refused; missing folders on the way are created (as writing would; with `create`
/// false only the nearest existing one is checked for write access) and the file is
/// opened for writing: an existing one for appending (its contents stay as they are), a
/// new one created and removed again.
void requireWritable(const std::filesystem::path& path, bool create = true);

} // namespace effigi::app
