// host/core/option_table.h: every option of a run in one table (scene key, command-line name,
// member, kind, range, help); the scene loader, the command-line flags and `rubble compare`'s
// KEY=VALUE pairs all read and check their values through it. Defaults are those of options.h.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include <glm/vec3.hpp>

#include "rubble/error.h"
#include "rubble/options.h"

namespace rubble {

/// How an option's value is written, deduced from its member's type.
enum class OptionKind {
    Number,      ///< a float member: any number, checked after its conversion to float
    WholeNumber, ///< an int member
    Choice,      ///< an enum member: one of its scene-file spellings
    Bool,        ///< true or false
    Vec3,        ///< three numbers: [x, y, z] in a file, x,y,z as text
    Text,        ///< any text
};

/// Which struct holds the member.
enum class OptionScope {
    Simulation, ///< SimulationOptions: a scene's `simulation` block, overridable per run
    Run,        ///< RunOptions: choices of the run, never in a scene
};

/// Where an option may be given besides a scene file (bits of Option::uses).
enum OptionUse : unsigned {
    kUseFlag = 1u,    ///< `--name VALUE` on run, view and render
    kUseCompare = 2u, ///< `name=VALUE` in `rubble compare --a/--b`
};

/// Allowed values of a number (compared after conversion to float) or a whole number. An open
/// bound is itself refused. Numbers must also be finite.
struct OptionRange {
    double min = -std::numeric_limits<double>::infinity(); ///< -inf: no lower bound
    double max = std::numeric_limits<double>::infinity();  ///< +inf: no upper bound
    bool minOpen = false, maxOpen = false;
};

/// An option's value once read from a file or from text, before its range check: double for
/// Number, int64 for WholeNumber, the spelling for Choice and Text, bool, dvec3 for Vec3.
using OptionValue = std::variant<double, std::int64_t, bool, std::string, glm::dvec3>;

/// What options are stored into: simulation options, run options, or both. A store of an
/// option whose struct is absent is a broken invariant (callers pick options by scope).
struct OptionTarget {
    SimulationOptions* simulation = nullptr;
    RunOptions* run = nullptr;
};

/// One option.
struct Option {
    std::string_view key{};   ///< scene path under `simulation` (`solver.iterations`); empty: run
    std::string_view name{};  ///< command-line spelling: `--name`, `name=` (`particle-spacing`)
    std::string_view alias{}; ///< a second compare key (`particle_spacing`); may be empty
    OptionScope scope = OptionScope::Simulation;
    unsigned uses = 0; ///< OptionUse bits
    OptionKind kind = OptionKind::Number;
    OptionRange range{};
    std::span<const std::string_view> choices{}; ///< Choice: the spellings, in the enum's order
    std::string_view unit{};      ///< SI unit of a number, for help and docs; may be empty
    std::string_view help{};      ///< what it sets, one phrase
    std::string_view unsetText{}; ///< what holds when the member is unset (optional members)

    /// Stores a checked value into the member.
    void (*store)(OptionTarget target, const OptionValue& value) = nullptr;
    /// The member's value; std::nullopt for an unset optional member.
    std::optional<OptionValue> (*load)(const SimulationOptions& simulation,
                                       const RunOptions& run) = nullptr;
};

/// Every option, in the order of the scene format's table.
std::span<const Option> optionTable();

/// The option with this scene path (`dt`, `solver.iterations`); nullptr if none.
const Option* findOptionByKey(std::string_view key);
/// The option with this command-line name or alias (`particle-spacing`); nullptr if none.
const Option* findOptionByName(std::string_view name);

/// Parses text (a flag's value, the VALUE of name=VALUE) into a value of the option's kind.
/// BadInput at `where` when it does not read as one; the range is not checked here.
Result<OptionValue> parseOptionText(const Option& option, std::string_view text,
                                    const std::string& where);

/// Checks a value against the option's kind and range (numbers after their conversion to
/// float, so 1e-300 is 0 and 1e40 is too large) and stores it. BadInput at `where` (a Vec3
/// component at `where[i]`); the message is the same whichever way the value came in.
Status assignOption(const Option& option, const OptionValue& value, const std::string& where,
                    OptionTarget target);

/// parseOptionText then assignOption.
Status assignOptionText(const Option& option, std::string_view text, const std::string& where,
                        OptionTarget target);

/// A value as command-line text (`0.016666668`, `cpu`, `0,-9.81,0`, `true`): the shortest that
/// reads back to the same float.
std::string optionText(const OptionValue& value);
/// A value as it is written in a scene file (`0.016666668`, `"cpu"`, `[0, -9.81, 0]`).
std::string optionJson(const OptionValue& value);

/// The default of an option (the member of a default SimulationOptions / RunOptions) as
/// command-line text, or its unsetText when the member is unset by default.
std::string optionDefaultText(const Option& option);
/// The allowed values in words: `> 0, s`, `integer from 1 to 100000`, `"cpu", "opencl"`.
std::string optionAllowedText(const Option& option);
/// The type shown after a flag in `--help`: FLOAT, INT, cpu|opencl, TEXT.
std::string optionTypeName(const Option& option);
/// The `--help` line of a flag: help, allowed values, scene key and default.
std::string optionFlagHelp(const Option& option);

/// The `simulation` table of docs/scene-format.md, in Markdown (key, default, allowed, meaning,
/// command line).
std::string simulationOptionsMarkdown();

/// The compare keys, for the message about an unknown one: `backend, collision, ... or dt`.
std::string compareKeysText();

} // namespace rubble
