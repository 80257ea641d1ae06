// host/gpu/kernel_source.h: the text of the one OpenCL program: every kernels/*.cl with the
// rubble/shared headers it includes pasted in once. Used at build time (host/gpu/tool, the
// embedded text) and at run time for RunOptions::kernelDir.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rubble/error.h"

namespace rubble::gpu {

/// One source file: its name (`integrate.cl`, `rubble/shared/body.h`) and text.
struct SourceFile {
    std::string name;
    std::string text;
};

/// Finds the text of an included header by its include path; std::nullopt when absent.
using IncludeResolver = std::function<std::optional<std::string>(const std::string&)>;

/// Concatenates the kernel files (in the given order) into one program. Each
/// `#include "..."` is replaced by the header's text the first time it appears and dropped
/// after; `#pragma once` lines go; `#line` directives keep build-log positions in the original
/// files. Errors: BadInput naming the file and line of an include that cannot be resolved.
Result<std::string> flattenProgram(const std::vector<SourceFile>& kernels,
                                   const IncludeResolver& resolve);

/// Reads every `*.cl` of a folder, sorted by name. Errors: Io naming the folder or file.
Result<std::vector<SourceFile>> readKernelFolder(const std::string& folder);

/// The program text from a kernel folder, with includes looked up in `includeDirs` in order
/// and then in `fallback` (the embedded headers).
Result<std::string> programFromFolder(const std::string& folder,
                                      const std::vector<std::string>& includeDirs,
                                      const std::vector<SourceFile>& fallback);

} // namespace rubble::gpu
