// host/io/trajectory_writer.cpp: CSV and JSON-lines trajectories. Numbers are written in the
// shortest form that reads back to the same float. Quaternions go back to the file order [w,x,y,z].
#include "host/io/trajectory_writer.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>

#include <unistd.h>

namespace rubble {
namespace {

constexpr std::size_t kFileBuffer = 1 << 20;

// Appends the shortest round-trip text of v.
void appendNumber(std::string& out, float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

// The JSON text of a body name (quotes and control characters escaped).
void appendJsonString(std::string& out, std::string_view s) {
    out += '"';
    for (char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += c;
        }
    }
    out += '"';
}

Error ioError(const std::string& path, const std::string& what) {
    return makeError(ErrorKind::Io, path, what + ": " + std::strerror(errno));
}

// Creates `path.<pid>.partial` (then .<pid>-1.partial, ...) that no other file holds: two runs
// writing the same output each write their own.
Result<std::pair<std::FILE*, std::string>> createPartial(const std::string& path) {
    const std::string stem = path + "." + std::to_string(::getpid());
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string partial = stem;
        if (attempt > 0) partial.append("-").append(std::to_string(attempt));
        partial.append(".partial");
        if (std::FILE* f = std::fopen(partial.c_str(), "wbx")) return std::pair{f, partial};
        if (errno != EEXIST) return ioError(partial, "cannot open for writing");
    }
    return ioError(stem + ".partial", "cannot find a free name for the temporary file");
}

} // namespace

TrajectoryWriter::TrajectoryWriter(std::string path, std::string partial,
                                   TrajectoryFormat format, std::FILE* file)
    : path_(std::move(path)), partial_(std::move(partial)), format_(format), file_(file),
      buffer_(new char[kFileBuffer]) {
    std::setvbuf(file_, buffer_.get(), _IOFBF, kFileBuffer);
}

TrajectoryWriter::TrajectoryWriter(TrajectoryWriter&& o) noexcept
    : path_(std::move(o.path_)), partial_(std::move(o.partial_)), format_(o.format_),
      file_(o.file_), buffer_(std::move(o.buffer_)), rows_(std::move(o.rows_)) {
    o.file_ = nullptr;
}

TrajectoryWriter& TrajectoryWriter::operator=(TrajectoryWriter&& o) noexcept {
    if (this != &o) {
        if (file_) std::fclose(file_);
        path_ = std::move(o.path_);
        partial_ = std::move(o.partial_);
        format_ = o.format_;
        file_ = o.file_;
        buffer_ = std::move(o.buffer_);
        rows_ = std::move(o.rows_);
        o.file_ = nullptr;
    }
    return *this;
}

TrajectoryWriter::~TrajectoryWriter() {
    if (file_) std::fclose(file_); // unfinished: the .partial file stays, under its own name
}

Result<TrajectoryWriter> TrajectoryWriter::open(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    TrajectoryFormat format;
    if (ext == ".csv")
        format = TrajectoryFormat::Csv;
    else if (ext == ".jsonl")
        format = TrajectoryFormat::Jsonl;
    else
        return makeError(ErrorKind::BadInput, "--out " + path,
                         "the trajectory file must end in .csv or .jsonl");
    Result<std::pair<std::FILE*, std::string>> partial = createPartial(path);
    RUBBLE_TRY(partial);
    std::FILE* f = partial->first;
    TrajectoryWriter w(path, partial->second, format, f);
    if (format == TrajectoryFormat::Csv)
        std::fputs("step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", f);
    return w;
}

Status TrajectoryWriter::write(const World& world) {
    rows_.resize(world.bodyCount());
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        rows_[i] = TrajectoryRow{world.bodyName(i), b.position, b.orientation, b.linearVelocity,
                                 b.angularVelocity};
    }
    return write(world.stepIndex(), world.time(), rows_);
}

Status TrajectoryWriter::write(std::int64_t step, double time,
                               std::span<const TrajectoryRow> rows) {
    // Time as a float: dt is a float, and the shortest float text reads 0.02 where the double
    // of 2 * 0.01f reads 0.019999999552965164. Well below a step's resolution for 10^6 steps.
    const float shownTime = float(time);
    std::string out;
    out.reserve(rows.size() * 160 + 64);
    if (format_ == TrajectoryFormat::Jsonl) {
        out += "{\"step\":" + std::to_string(step) + ",\"time\":";
        appendNumber(out, shownTime);
        out += ",\"bodies\":[";
    }
    static const char* const kKeys[] = {"px", "py", "pz", "qw", "qx", "qy", "qz",
                                        "vx", "vy", "vz", "wx", "wy", "wz"};
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const TrajectoryRow& b = rows[i];
        const float values[13] = {b.position.x,       b.position.y,        b.position.z,
                                  b.orientation.w,    b.orientation.x,     b.orientation.y,
                                  b.orientation.z,    b.linearVelocity.x,  b.linearVelocity.y,
                                  b.linearVelocity.z, b.angularVelocity.x, b.angularVelocity.y,
                                  b.angularVelocity.z};
        if (format_ == TrajectoryFormat::Csv) {
            out += std::to_string(step);
            out += ',';
            appendNumber(out, shownTime);
            out += ',';
            out += b.body;
            for (float v : values) {
                out += ',';
                appendNumber(out, v);
            }
            out += '\n';
        } else {
            out += i ? ",{\"body\":" : "{\"body\":";
            appendJsonString(out, b.body);
            for (int k = 0; k < 13; ++k) {
                out += ",\"";
                out += kKeys[k];
                out += "\":";
                appendNumber(out, values[k]);
            }
            out += '}';
        }
    }
    if (format_ == TrajectoryFormat::Jsonl) out += "]}\n";
    if (std::fwrite(out.data(), 1, out.size(), file_) != out.size())
        return ioError(partialPath(), "write failed");
    return {};
}

Status TrajectoryWriter::finish() {
    std::FILE* f = file_;
    file_ = nullptr;
    if (std::fclose(f) != 0) return ioError(partialPath(), "close failed");
    if (std::rename(partialPath().c_str(), path_.c_str()) != 0)
        return ioError(path_, "cannot rename " + partialPath() + " to it");
    return {};
}

Status writeFileAtomically(const std::string& path, const std::string& text) {
    Result<AtomicFile> file = AtomicFile::create(path);
    RUBBLE_TRY(file);
    return file->commit(text);
}

Result<AtomicFile> AtomicFile::create(const std::string& path) {
    Result<std::pair<std::FILE*, std::string>> partial = createPartial(path);
    RUBBLE_TRY(partial);
    AtomicFile a;
    a.path_ = path;
    a.partial_ = partial->second;
    a.file_ = partial->first;
    return a;
}

AtomicFile::AtomicFile(AtomicFile&& o) noexcept
    : path_(std::move(o.path_)), partial_(std::move(o.partial_)), file_(o.file_) {
    o.file_ = nullptr;
}

AtomicFile::~AtomicFile() {
    if (!file_) return;
    // Never committed: no half-written file stays behind.
    std::fclose(file_);
    std::remove(partial_.c_str());
}

Status AtomicFile::commit(const std::string& text) {
    std::FILE* f = file_;
    file_ = nullptr;
    const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (std::fclose(f) != 0 || !written) {
        const Error e = ioError(partial_, "write failed");
        std::remove(partial_.c_str());
        return e;
    }
    if (std::rename(partial_.c_str(), path_.c_str()) != 0)
        return ioError(path_, "cannot rename " + partial_ + " to it");
    return {};
}

} // namespace rubble
