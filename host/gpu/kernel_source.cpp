// host/gpu/kernel_source.cpp: flattening kernel files and their shared headers into one program.
#include "host/gpu/kernel_source.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace rubble::gpu {
namespace {

std::optional<std::string> readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// The quoted path of an `#include "..."` line, if the line is one.
std::optional<std::string> includedPath(const std::string& line) {
    std::size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line[i] != '#') return std::nullopt;
    i = line.find_first_not_of(" \t", i + 1);
    if (i == std::string::npos || line.compare(i, 7, "include") != 0) return std::nullopt;
    const std::size_t open = line.find('"', i + 7);
    const std::size_t close = open == std::string::npos ? open : line.find('"', open + 1);
    if (close == std::string::npos) return std::nullopt;
    return line.substr(open + 1, close - open - 1);
}

bool isPragmaOnce(const std::string& line) {
    std::string compact;
    for (char c : line)
        if (c != ' ' && c != '\t') compact += c;
    return compact == "#pragmaonce";
}

class Flattener {
  public:
    explicit Flattener(const IncludeResolver& resolve) : resolve_(resolve) {}

    Status append(const std::string& name, const std::string& text) {
        out_ += "#line 1 \"" + name + "\"\n";
        std::istringstream lines(text);
        std::string line;
        int number = 0;
        while (std::getline(lines, line)) {
            ++number;
            if (isPragmaOnce(line)) {
                out_ += "\n";
                continue;
            }
            const std::optional<std::string> path = includedPath(line);
            if (!path) {
                out_ += line + "\n";
                continue;
            }
            if (!done_.insert(*path).second) {
                out_ += "\n";
                continue;
            }
            const std::optional<std::string> header = resolve_(*path);
            if (!header)
                return makeError(ErrorKind::BadInput, name + ":" + std::to_string(number),
                                 "cannot find the included file \"" + *path + "\"");
            RUBBLE_TRY(append(*path, *header));
            out_ += "#line " + std::to_string(number + 1) + " \"" + name + "\"\n";
        }
        return {};
    }
    std::string take() { return std::move(out_); }

  private:
    const IncludeResolver& resolve_;
    std::set<std::string> done_;
    std::string out_;
};

} // namespace

Result<std::string> flattenProgram(const std::vector<SourceFile>& kernels,
                                   const IncludeResolver& resolve) {
    Flattener f(resolve);
    for (const SourceFile& k : kernels) RUBBLE_TRY(f.append(k.name, k.text));
    return f.take();
}

Result<std::vector<SourceFile>> readKernelFolder(const std::string& folder) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        return makeError(ErrorKind::Io, folder, "is not a folder of kernel (.cl) files");
    std::vector<SourceFile> files;
    for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
        if (e.path().extension() != ".cl") continue;
        std::optional<std::string> text = readFile(e.path());
        if (!text) return makeError(ErrorKind::Io, e.path().string(), "cannot be read");
        files.push_back({e.path().filename().string(), std::move(*text)});
    }
    if (ec) return makeError(ErrorKind::Io, folder, "cannot be listed: " + ec.message());
    if (files.empty()) return makeError(ErrorKind::Io, folder, "holds no kernel (.cl) files");
    std::sort(files.begin(), files.end(),
              [](const SourceFile& x, const SourceFile& y) { return x.name < y.name; });
    return files;
}

Result<std::string> programFromFolder(const std::string& folder,
                                      const std::vector<std::string>& includeDirs,
                                      const std::vector<SourceFile>& fallback) {
    Result<std::vector<SourceFile>> kernels = readKernelFolder(folder);
    RUBBLE_TRY(kernels);
    const IncludeResolver resolve = [&](const std::string& path) -> std::optional<std::string> {
        for (const std::string& dir : includeDirs)
            if (std::optional<std::string> text = readFile(std::filesystem::path(dir) / path))
                return text;
        for (const SourceFile& f : fallback)
            if (f.name == path) return f.text;
        return std::nullopt;
    };
    return flattenProgram(*kernels, resolve);
}

} // namespace rubble::gpu
