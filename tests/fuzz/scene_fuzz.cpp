// tests/fuzz/scene_fuzz.cpp: libFuzzer target for the scene loader: any text is loaded, and a
// scene that loads is built into a world and stepped twice. Nothing may crash, hang or leak; bad
// input must come back as an Error. Corpus: scenes/ (tests/fuzz/CMakeLists.txt, .ci/run).
#include <cstddef>
#include <cstdint>
#include <string>

#include "rubble/world.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    // Meshes named by the corpus resolve against the example scenes' folder.
    rubble::Result<rubble::Scene> scene =
        rubble::parseScene(text, "fuzz.json", RUBBLE_SOURCE_DIR "/scenes");
    if (!scene) return 0;
    // Large generated scenes are valid but slow: building them tests nothing new.
    if (scene->bodies.size() > 2000) return 0;
    scene->simulation.backend = rubble::Backend::Cpu;
    rubble::Result<rubble::World> world = rubble::World::create(*scene);
    if (!world) return 0;
    for (int i = 0; i < 2; ++i)
        if (!world->step()) break;
    return 0;
}
