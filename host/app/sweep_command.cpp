// host/app/sweep_command.cpp: `rubble sweep SWEEP.json`: a parameter sweep on Dask, which lives
// in the Python package (python/rubble/_sweep.py, also `python3 -m rubble sweep`); this hands the
// arguments to the package's interpreter.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "host/app/commands.h"

namespace rubble::app {
namespace {

// Imports the package's sweep module, or says what is missing and how to get it.
constexpr const char* kBootstrap =
    "import sys\n"
    "try:\n"
    "    from rubble._sweep import main\n"
    "except ImportError as e:\n"
    "    sys.stderr.write('rubble: sweep: the Python package rubble is not installed for ' +\n"
    "                     sys.executable + ' (' + str(e) + '); install it with pip install . '\n"
    "                     'from the rubble checkout (docs/python.md), or name its interpreter in '\n"
    "                     'RUBBLE_PYTHON\\n')\n"
    "    sys.exit(1)\n"
    "sys.exit(main(sys.argv[1:]))\n";

} // namespace

void sweepFromEnvironment(SweepArgs& args) {
    if (const char* p = std::getenv("RUBBLE_PYTHON"); p && *p) args.python = p;
}

int sweepCommand(const SweepArgs& args) {
    std::vector<std::string> words = {args.python, "-c", kBootstrap, args.file};
    if (args.workers) words.insert(words.end(), {"--workers", std::to_string(*args.workers)});
    if (!args.scheduler.empty()) words.insert(words.end(), {"--scheduler", args.scheduler});
    if (!args.out.empty()) words.insert(words.end(), {"--out", args.out});
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    std::fflush(stdout);
    execvp(argv[0], argv.data());
    // Only reached when the interpreter could not be started.
    std::fprintf(stderr,
                 "rubble: sweep: cannot run %s (%s); the sweep runs in the Python package "
                 "rubble: install it (docs/python.md) and put its python3 on PATH, or name it "
                 "in RUBBLE_PYTHON\n",
                 args.python.c_str(), std::strerror(errno));
    return kExitFailure;
}

} // namespace rubble::app
