// host/io/trajectory_writer.h: trajectories as CSV or JSON lines (SCENE_FORMAT.md, Outputs),
// written under a temporary name and renamed when complete.
#pragma once

#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/error.h"
#include "rubble/world.h"

namespace rubble {

enum class TrajectoryFormat { Csv, Jsonl };

/// One body's row of a written step: world frame, SI units.
struct TrajectoryRow {
    std::string_view body;
    glm::vec3 position{0.0f};
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 linearVelocity{0.0f};
    glm::vec3 angularVelocity{0.0f};
};

/// Writes one row per body per written step. The file is `path.<pid>.partial` (a name no other
/// file has) until finish(); a run that stops early leaves the partial file, never a truncated
/// file under the final name.
class TrajectoryWriter {
  public:
    /// Creates `path.<pid>.partial` for writing (so that the folder is known to be writable
    /// before any step). The format follows the extension (.csv or .jsonl); anything else is
    /// BadInput at `--out`; a folder that is missing or not writable is Io.
    static Result<TrajectoryWriter> open(const std::string& path);

    TrajectoryWriter(TrajectoryWriter&&) noexcept;
    TrajectoryWriter& operator=(TrajectoryWriter&&) noexcept;
    ~TrajectoryWriter();

    /// Appends the world's current state: step, time and every body.
    Status write(const World& world);
    /// Appends one step given as rows (for programs that are not a World, such as the peers
    /// of the benchmarks).
    Status write(std::int64_t step, double time, std::span<const TrajectoryRow> rows);
    /// Flushes, closes and renames the file to its final name.
    Status finish();

    const std::string& path() const { return path_; }
    const std::string& partialPath() const { return partial_; }

  private:
    TrajectoryWriter(std::string path, std::string partial, TrajectoryFormat format,
                     std::FILE* file);
    std::string path_, partial_;
    TrajectoryFormat format_;
    std::FILE* file_;
    std::unique_ptr<char[]> buffer_;
    std::vector<TrajectoryRow> rows_; // reused by write(World)
};

/// Writes `text` to `path` through a temporary file renamed into place.
Status writeFileAtomically(const std::string& path, const std::string& text);

/// A file written whole at the end, created at the start: `path.<pid>.partial` exists from
/// create() (so a missing or read-only folder is known before the work that fills it) and is
/// renamed to `path` by commit(); dropped uncommitted, it is removed.
class AtomicFile {
  public:
    /// Errors: Io naming the temporary file.
    static Result<AtomicFile> create(const std::string& path);
    AtomicFile(AtomicFile&&) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    ~AtomicFile();
    /// Writes `text`, closes and renames. Errors: Io.
    Status commit(const std::string& text);
    const std::string& path() const { return path_; }

  private:
    AtomicFile() = default;
    std::string path_, partial_;
    std::FILE* file_ = nullptr;
};

} // namespace rubble
