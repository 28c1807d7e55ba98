#pragma once
// Untrusted input: the files a scene names, and text quoted from them in messages.
// Every file reader checks its path here, so that a device, a FIFO or a folder given as a
// file is refused with one line (reading /dev/zero never ends; opening a FIFO blocks
// until someone writes to it) and the work a reader does is bounded by a real file's
// size. Every message that quotes input quotes it through excerpt(), so that newlines,
// control bytes or invalid UTF-8 in a file cannot break the one-line error.
#include "effigi/core/error.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace effigi {

/// `text` taken from input, fit to quote inside a one-line message: printable ASCII and
/// valid UTF-8 kept; backslash, newline, carriage return and tab escaped as \\ \n \r \t;
/// every other control byte (C0, DEL, the C1 range and U+2028/U+2029 line separators)
/// and every byte that is not part of valid UTF-8 written as \xNN. Cut after `maxChars`
/// characters (an escape counts as one), with "…" appended when something was cut.
std::string excerpt(std::string_view text, std::size_t maxChars = 40);

/// The size in bytes of `path`, which must name a regular file (symbolic links followed).
/// Otherwise throws an Error at `where` (the scene line naming the file; may be unknown):
/// "<path>: cannot read <what>: <why>", `what` saying what the file was to be ("PLY
/// file"), why: no such file, a directory, a character or block device, a FIFO or a
/// socket, or the system's reason (permission denied...).
std::uint64_t regularFileSize(const std::filesystem::path& path, std::string_view what,
                              const SourceLocation& where = {});

/// The whole content of the regular file `path`, refused as regularFileSize() refuses it.
/// The check is made on the opened descriptor (opened without blocking, so a FIFO is
/// refused rather than waited on), and no more than the size it has then is read.
std::string readRegularFile(const std::filesystem::path& path, std::string_view what,
                            const SourceLocation& where = {});

} // namespace effigi
