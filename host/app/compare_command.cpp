// host/app/compare_command.cpp: `rubble compare SCENE --a K=V... --b K=V...`.
#include "host/app/commands.h"
#include "host/app/gpu_commands.h"

namespace rubble::app {

int compareCommand(const CompareArgs&) {
    return report(makeError(ErrorKind::NotSupported, "compare", "is not built yet"));
}

} // namespace rubble::app
