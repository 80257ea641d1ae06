// host/gpu/embedded_kernels.h: the kernel program and shared headers as text, generated at
// build time by host/gpu/tool/embed_kernels.cpp from kernels/*.cl and include/rubble/shared.
#pragma once

#include <string_view>

namespace rubble::gpu {

/// The flattened program: every kernels/*.cl with its shared headers pasted in once.
extern const std::string_view kEmbeddedProgram;

/// One shared header's text by its include path (`rubble/shared/body.h`).
struct EmbeddedHeader {
    std::string_view name;
    std::string_view text;
};
extern const EmbeddedHeader kEmbeddedHeaders[];
extern const unsigned kEmbeddedHeaderCount;

} // namespace rubble::gpu
