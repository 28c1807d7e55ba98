#pragma once
// Checkpoints of a progressive render (effigi render --checkpoint DIR / --resume DIR): the
// running sums of the film and of the renderer (IAccumulator), the job's progress, the
// sample indices each process (MPI rank) has used with its seed, and the identity of the
// scene and options, so that a killed render continues where its last checkpoint left it
// with samples never drawn before.
//
// A checkpoint is one file, DIR/checkpoint.effigi, replaced atomically: written to a
// temporary file in DIR, flushed to disk (fsync), renamed over the old one, and the
// directory flushed. A process killed at any moment leaves either the old file or the new
// one, never a torn one; the header's length and checksum let the reader refuse anything
// else (a file truncated or damaged later) with one line.
//
// Layout (native little-endian): "EFFIGICK", u32 format version, u32 0, u64 payload bytes,
// u64 checksum of the payload (FNV-1a over 64-bit words), then the payload: identity,
// scene path, budget (spp, seconds, relMSE target), progress (spp, seconds, samples,
// rejected samples), per-process sample counts, then the film's and the renderer's sums
// (layout, floats, doubles).
#include "effigi/interfaces/iaccumulator.hpp"
#include "effigi/render/progressive.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace effigi {

struct Checkpoint {
    std::uint64_t identity = 0;  ///< checkpointIdentity() of the render it was written by
    std::string scene;           ///< the scene file, for messages
    /// The budget the render was started with (a resume without one keeps it).
    std::uint64_t spp = 0;
    double timeBudget = 0.0, targetRelMSE = 0.0;
    PassReport report;                      ///< the job's progress (processSpp unused)
    std::vector<std::uint64_t> processSpp;  ///< sample indices each process (rank) has used
    AccumulatorSums film, renderer;
};

/// The identity a checkpoint must match to be resumed: the scene file's bytes, the -D
/// definitions and the seed. Throws effigi::Error if the scene cannot be read.
std::uint64_t checkpointIdentity(const std::filesystem::path& scene, const std::map<std::string, std::string>& defines,
                                 std::uint64_t seed);

/// DIR/checkpoint.effigi
std::filesystem::path checkpointFile(const std::filesystem::path& dir);

/// Write `c` atomically into `dir` (created if missing); returns the bytes written.
/// Throws effigi::Error "cannot write checkpoint <file>: <reason>".
std::uint64_t writeCheckpoint(const std::filesystem::path& dir, const Checkpoint& c);

/// Read the checkpoint of `dir`. Throws effigi::Error naming the file when it is missing,
/// not a checkpoint, of another format version, truncated or damaged (checksum), or when
/// its fields cannot be what a render wrote (a length past the end, a time or budget that
/// is negative or not finite, a sum that is not finite).
Checkpoint readCheckpoint(const std::filesystem::path& dir);

/// The header of a checkpoint file holding `payload` (magic, version, length, checksum),
/// which the payload follows. writeCheckpoint writes it; the fuzz target frames its inputs
/// with it so that they reach the field parser behind the checksum.
std::string checkpointHeader(std::string_view payload);

} // namespace effigi
