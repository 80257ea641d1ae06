// host/app/overrides.cpp: command-line flags of the option table (host/core/option_table.h),
// the overrides they give, and error reporting.
#include <cstdio>

#include <CLI/CLI.hpp>

#include "host/app/commands.h"
#include "host/core/assert.h"

namespace rubble::app {
namespace {

std::string flagOf(const Option& option) { return "--" + std::string(option.name); }

void addFlag(CLI::App* cmd, const Option& option, Overrides& o) {
    RUBBLE_ASSERT(option.scope == OptionScope::Simulation && (option.uses & kUseFlag));
    const Option* p = &option;
    cmd->add_option_function<std::string>(
           flagOf(option),
           [p, &o](const std::string& text) { o.items.push_back({p, flagOf(*p), text}); },
           optionFlagHelp(option))
        ->type_name(optionTypeName(option));
}

// A run option is read as soon as it is parsed; its kinds (text, a flag) always read.
void addFlag(CLI::App* cmd, const Option& option, RunOptions& run) {
    RUBBLE_ASSERT(option.scope == OptionScope::Run && (option.uses & kUseFlag));
    const Option* p = &option;
    auto assign = [p, &run](const std::string& text) {
        if (Status s = assignOptionText(*p, text, flagOf(*p), OptionTarget{nullptr, &run}); !s)
            throw CLI::ValidationError(s.error().describe());
    };
    if (option.kind == OptionKind::Bool) // --flag, or --flag=false
        cmd->add_flag_function(
            flagOf(option), [assign](std::int64_t count) { assign(count > 0 ? "true" : "false"); },
            optionFlagHelp(option));
    else
        cmd->add_option_function<std::string>(flagOf(option), assign, optionFlagHelp(option))
            ->type_name(optionTypeName(option));
}

const Option& optionNamed(std::string_view name) {
    const Option* option = findOptionByName(name);
    RUBBLE_ASSERT(option != nullptr);
    return *option;
}

} // namespace

Status applyOverrides(const Overrides& o, Scene& scene) {
    for (const Overrides::Item& item : o.items)
        RUBBLE_TRY(assignOptionText(*item.option, item.text, item.where,
                                    OptionTarget{&scene.simulation, nullptr}));
    return {};
}

void addOverrideFlags(CLI::App* cmd, Overrides& o) {
    for (const Option& option : optionTable())
        if (option.scope == OptionScope::Simulation && (option.uses & kUseFlag))
            addFlag(cmd, option, o);
}

void addOverrideFlag(CLI::App* cmd, std::string_view name, Overrides& o) {
    addFlag(cmd, optionNamed(name), o);
}

void addRunFlags(CLI::App* cmd, RunOptions& run) {
    for (const Option& option : optionTable())
        if (option.scope == OptionScope::Run && (option.uses & kUseFlag)) addFlag(cmd, option, run);
}

void addRunFlag(CLI::App* cmd, std::string_view name, RunOptions& run) {
    addFlag(cmd, optionNamed(name), run);
}

void reportWarnings(const World& world) {
    for (const Warning& w : world.warnings())
        std::fprintf(stderr, "rubble: warning: %s\n", w.describe().c_str());
}

int report(const Error& e) {
    std::fprintf(stderr, "rubble: %s\n", e.describe().c_str());
    switch (e.kind) {
    case ErrorKind::BadInput:
    case ErrorKind::NotSupported:
        return kExitBadInput;
    case ErrorKind::Numerical:
        return kExitNumerical;
    case ErrorKind::Limit:
        return kExitLimit;
    case ErrorKind::Interrupted:
        return kExitInterrupted;
    default:
        return kExitFailure;
    }
}

} // namespace rubble::app
