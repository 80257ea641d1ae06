// host/app/solvers_command.cpp: `rubble solvers SCENE --step N`.
#include "host/app/commands.h"
#include "host/app/gpu_commands.h"

namespace rubble::app {

int solversCommand(const SolversArgs&) {
    return report(makeError(ErrorKind::NotSupported, "solvers", "is not built yet"));
}

} // namespace rubble::app
