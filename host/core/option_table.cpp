// host/core/option_table.cpp: the table of options and the one parser and range check that the
// scene loader, the command-line flags and `rubble compare` share (option_table.h).
#include "host/core/option_table.h"

#include <charconv>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

#include "host/core/assert.h"
#include "rubble/scene.h"

namespace rubble {
namespace {

// ---- The member an option sets, reached through a chain of member pointers.

template <auto... Path, class Root> auto& memberOf(Root& root) { return (root .* ... .* Path); }

template <class T> struct IsOptional : std::false_type {};
template <class T> struct IsOptional<std::optional<T>> : std::true_type {
    using Value = T;
};

template <class T> constexpr OptionKind kindOf() {
    if constexpr (IsOptional<T>::value) return kindOf<typename IsOptional<T>::Value>();
    else if constexpr (std::is_same_v<T, float>) return OptionKind::Number;
    else if constexpr (std::is_same_v<T, int>) return OptionKind::WholeNumber;
    else if constexpr (std::is_same_v<T, bool>) return OptionKind::Bool;
    else if constexpr (std::is_same_v<T, glm::vec3>) return OptionKind::Vec3;
    else if constexpr (std::is_same_v<T, std::string>) return OptionKind::Text;
    else {
        static_assert(std::is_enum_v<T>, "an option member is a number, bool, vec3, text or enum");
        return OptionKind::Choice;
    }
}

template <class T> std::span<const std::string_view> choicesOf() {
    if constexpr (IsOptional<T>::value) return choicesOf<typename IsOptional<T>::Value>();
    else if constexpr (std::is_enum_v<T>) return spellings<T>();
    else return {};
}

// Values into members; the value was checked by assignOption, so its alternative is the kind's.
void put(float& m, const OptionValue& v) { m = float(std::get<double>(v)); }
void put(int& m, const OptionValue& v) { m = int(std::get<std::int64_t>(v)); }
void put(bool& m, const OptionValue& v) { m = std::get<bool>(v); }
void put(std::string& m, const OptionValue& v) { m = std::get<std::string>(v); }
void put(glm::vec3& m, const OptionValue& v) {
    const glm::dvec3 d = std::get<glm::dvec3>(v);
    m = glm::vec3(float(d.x), float(d.y), float(d.z));
}
template <class E>
    requires std::is_enum_v<E>
void put(E& m, const OptionValue& v) {
    const std::span<const std::string_view> names = spellings<E>();
    for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i] == std::get<std::string>(v)) m = static_cast<E>(i);
}
template <class E> void put(std::optional<E>& m, const OptionValue& v) {
    E e{};
    put(e, v);
    m = e;
}

// Members into values.
std::optional<OptionValue> get(float m) { return double(m); }
std::optional<OptionValue> get(int m) { return std::int64_t(m); }
std::optional<OptionValue> get(bool m) { return m; }
std::optional<OptionValue> get(const std::string& m) { return m; }
std::optional<OptionValue> get(const glm::vec3& m) { return glm::dvec3(m); }
template <class E>
    requires std::is_enum_v<E>
std::optional<OptionValue> get(E m) {
    return std::string(spellings<E>()[static_cast<std::size_t>(m)]);
}
template <class E> std::optional<OptionValue> get(const std::optional<E>& m) {
    if (!m) return std::nullopt;
    return get(*m);
}

// An option on a member of SimulationOptions (Path from it) or of RunOptions.
template <auto... Path> Option simulationOption(Option o) {
    using T = std::remove_cvref_t<decltype(memberOf<Path...>(std::declval<SimulationOptions&>()))>;
    o.scope = OptionScope::Simulation;
    o.kind = kindOf<T>();
    o.choices = choicesOf<T>();
    o.store = [](OptionTarget t, const OptionValue& v) {
        RUBBLE_ASSERT(t.simulation != nullptr);
        put(memberOf<Path...>(*t.simulation), v);
    };
    o.load = [](const SimulationOptions& s, const RunOptions&) {
        return get(memberOf<Path...>(s));
    };
    return o;
}

template <auto... Path> Option runOption(Option o) {
    using T = std::remove_cvref_t<decltype(memberOf<Path...>(std::declval<RunOptions&>()))>;
    o.scope = OptionScope::Run;
    o.kind = kindOf<T>();
    o.choices = choicesOf<T>();
    o.store = [](OptionTarget t, const OptionValue& v) {
        RUBBLE_ASSERT(t.run != nullptr);
        put(memberOf<Path...>(*t.run), v);
    };
    o.load = [](const SimulationOptions&, const RunOptions& r) {
        return get(memberOf<Path...>(r));
    };
    return o;
}

constexpr unsigned kEverywhere = kUseFlag | kUseCompare;
constexpr double kMaxSteps = 1e9;
constexpr double kMaxIterations = 1e5;
constexpr double kMaxSubsteps = 1000;

// The table. Defaults are not written here: they are the members' initialisers in options.h.
const std::vector<Option>& table() {
    using S = SimulationOptions;
    static const std::vector<Option> options = {
        simulationOption<&S::dt>({.key = "dt",
                                  .name = "dt",
                                  .uses = kEverywhere,
                                  .range = {.min = 0, .minOpen = true},
                                  .unit = "s",
                                  .help = "Time step"}),
        simulationOption<&S::steps>({.key = "steps",
                                     .name = "steps",
                                     .uses = kUseFlag,
                                     .range = {.min = 0, .max = kMaxSteps},
                                     .help = "Steps that rubble run takes"}),
        simulationOption<&S::gravity>({.key = "gravity",
                                       .name = "gravity",
                                       .unit = "m/s²",
                                       .help = "Gravity, world frame (y up)"}),
        simulationOption<&S::integrator>(
            {.key = "integrator",
             .name = "integrator",
             .uses = kEverywhere,
             .help = "Time integration of the bodies (docs/integrators.md)"}),
        simulationOption<&S::backend>({.key = "backend",
                                       .name = "backend",
                                       .uses = kEverywhere,
                                       .help = "Where the bodies are stepped"}),
        simulationOption<&S::collision, &CollisionOptions::method>(
            {.key = "collision.method",
             .name = "collision",
             .uses = kEverywhere,
             .help = "How contacts are found",
             .unsetText = "sat on cpu, particles on opencl"}),
        simulationOption<&S::collision, &CollisionOptions::particleSpacing>(
            {.key = "collision.particle_spacing",
             .name = "particle-spacing",
             .alias = "particle_spacing",
             .uses = kEverywhere,
             .range = {.min = kMinLength, .max = kMaxLength},
             .unit = "m",
             .help = "Voxel size of the particle shapes"}),
        simulationOption<&S::collision, &CollisionOptions::recycleContacts>(
            {.key = "collision.recycle_contacts",
             .name = "recycle-contacts",
             .uses = kEverywhere,
             .help = "SAT on the cpu backend: hull pairs, and bodies on static meshes, that "
                     "moved less than 0.25 mm against each other keep their manifolds, their "
                     "depths recomputed (docs/collision.md)"}),
        simulationOption<&S::solver, &SolverOptions::type>({.key = "solver.type",
                                                            .name = "solver",
                                                            .uses = kEverywhere,
                                                            .help = "Contact and joint solver",
                                                            .unsetText = "pgs"}),
        simulationOption<&S::solver, &SolverOptions::iterations>(
            {.key = "solver.iterations",
             .name = "iterations",
             .uses = kEverywhere,
             .range = {.min = 1, .max = kMaxIterations},
             .help = "Solver sweeps per step"}),
        simulationOption<&S::solver, &SolverOptions::baumgarte>(
            {.key = "solver.baumgarte",
             .name = "baumgarte",
             .range = {.min = 0, .max = 1},
             .help = "Fraction of the penetration corrected per step"}),
        simulationOption<&S::solver, &SolverOptions::slop>(
            {.key = "solver.slop",
             .name = "slop",
             .range = {.min = 0},
             .unit = "m",
             .help = "Penetration left uncorrected"}),
        simulationOption<&S::solver, &SolverOptions::relaxation>(
            {.key = "solver.relaxation",
             .name = "relaxation",
             .range = {.min = 0, .max = 2, .minOpen = true, .maxOpen = true},
             .help = "Over- or under-relaxation of each impulse update (from 2 on the iteration "
                     "diverges)"}),
        simulationOption<&S::solver, &SolverOptions::warmStart>(
            {.key = "solver.warm_start",
             .name = "warm-start",
             .help = "Start from the last step's impulses, matched by feature id"}),
        simulationOption<&S::continuous>(
            {.key = "continuous",
             .name = "continuous",
             .uses = kEverywhere,
             .help = "Speculative contacts widened by each pair's motion in the step, so that "
                     "fast bodies do not tunnel (docs/collision.md)"}),
        simulationOption<&S::solver, &SolverOptions::substeps>(
            {.key = "solver.substeps",
             .name = "substeps",
             .uses = kEverywhere,
             .range = {.min = 1, .max = kMaxSubsteps},
             .help = "Soft step: substeps per step, each one biased pass"}),
        simulationOption<&S::solver, &SolverOptions::relaxIterations>(
            {.key = "solver.relax_iterations",
             .name = "relax-iterations",
             .uses = kEverywhere,
             .range = {.min = 0, .max = kMaxSubsteps},
             .help = "Soft step: passes without bias after each substep's positions"}),
        simulationOption<&S::solver, &SolverOptions::contactHertz>(
            {.key = "solver.contact_hertz",
             .name = "contact-hertz",
             .uses = kEverywhere,
             .range = {.min = 0, .minOpen = true},
             .unit = "Hz",
             .help = "Soft step: contact stiffness (at most a quarter of the substep rate is "
                     "used)"}),
        simulationOption<&S::solver, &SolverOptions::dampingRatio>(
            {.key = "solver.damping_ratio",
             .name = "damping-ratio",
             .uses = kEverywhere,
             .range = {.min = 0},
             .help = "Soft step: contact damping ratio"}),
        simulationOption<&S::solver, &SolverOptions::jointHertz>(
            {.key = "solver.joint_hertz",
             .name = "joint-hertz",
             .uses = kEverywhere,
             .range = {.min = 0, .minOpen = true},
             .unit = "Hz",
             .help = "Soft step: joint stiffness"}),
        simulationOption<&S::solver, &SolverOptions::jointDampingRatio>(
            {.key = "solver.joint_damping_ratio",
             .name = "joint-damping-ratio",
             .uses = kEverywhere,
             .range = {.min = 0},
             .help = "Soft step: joint damping ratio"}),
        simulationOption<&S::solver, &SolverOptions::maxPushSpeed>(
            {.key = "solver.max_push_speed",
             .name = "max-push-speed",
             .uses = kEverywhere,
             .range = {.min = 0, .minOpen = true},
             .unit = "m/s",
             .help = "Soft step: fastest a contact pushes penetrating bodies apart"}),
        simulationOption<&S::coupling>({.key = "coupling",
                                        .name = "coupling",
                                        .help = "Whether debris on the device pushes the bodies "
                                                "on the CPU"}),
        simulationOption<&S::sleep>({.key = "sleep",
                                     .name = "sleep",
                                     .uses = kEverywhere,
                                     .help = "Whether still bodies go to sleep; false keeps "
                                             "every body awake"}),
        runOption<&RunOptions::device>({.name = "device",
                                        .uses = kEverywhere,
                                        .help = "OpenCL device: a name fragment or an index"}),
        runOption<&RunOptions::kernelDir>(
            {.name = "kernel-dir", .uses = kUseFlag, .help = "Load kernels/*.cl from this folder"}),
        runOption<&RunOptions::deterministic>(
            {.name = "deterministic",
             .uses = kEverywhere,
             .help = "Sort device rows so runs repeat bit for bit"}),
        runOption<&RunOptions::pgsBlocks>(
            {.name = "pgs-blocks",
             .uses = kEverywhere,
             .range = {.min = -1, .max = 65536},
             .help = "Blocks of the device's PGS solve: -1 as the device suits (4 per compute "
                     "unit on a CPU device, one per 128 bodies if fewer; none on a GPU), 0 "
                     "every element colored"}),
        runOption<&RunOptions::pgsColoring>(
            {.name = "pgs-coloring",
             .uses = kEverywhere,
             .help = "Who colors the device's solve without blocks: the device (fixed "
                     "colors, no read back), the host (by support, a read each step), or auto "
                     "(the device for the soft step, the host for PGS)"}),
        runOption<&RunOptions::bodySleep>(
            {.name = "body-sleep",
             .uses = kEverywhere,
             .help = "SAT on the device: bodies sleep one by one instead of by islands"}),
        runOption<&RunOptions::buildOptions>(
            {.name = "build-options",
             .uses = kUseFlag,
             .help = "Added to the OpenCL program's build options (-cl-opt-disable for "
                     "Oclgrind)"}),
    };
    return options;
}

// ---- Text of numbers and values.

// A bound or a component: whole numbers in full (1000000000, not 1e+09), short fractions in
// fixed notation (0.0001, not 1e-04), others shortest.
std::string shortest(double v) {
    if (v == std::trunc(v) && std::abs(v) < 1e15) return std::to_string(std::int64_t(v));
    char buf[64];
    constexpr std::ptrdiff_t kLongestFixed = 8;
    const auto fixed = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed);
    if (fixed.ec == std::errc() && fixed.ptr - buf <= kLongestFixed)
        return std::string(buf, fixed.ptr);
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

// A float member's value: the shortest text that reads back to the same float.
std::string shortestFloat(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, float(v));
    return std::string(buf, r.ptr);
}

// left + s + right (appended: GCC 12 misreads "x" + std::string(s) as an overlapping copy).
std::string enclose(std::string_view left, std::string_view s, std::string_view right) {
    std::string out;
    out.reserve(left.size() + s.size() + right.size());
    out.append(left).append(s).append(right);
    return out;
}

std::string quoted(std::string_view s) { return enclose("\"", s, "\""); }
std::string code(std::string_view s) { return enclose("`", s, "`"); }

// "a, b or c" with last = " or ", "a|b|c" with separator = last = "|".
std::string listText(std::span<const std::string_view> items, std::string_view last,
                     bool quote = false, std::string_view separator = ", ") {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += i + 1 == items.size() ? last : separator;
        out += quote ? quoted(items[i]) : std::string(items[i]);
    }
    return out;
}

bool hasMin(const OptionRange& r) { return std::isfinite(r.min); }
bool hasMax(const OptionRange& r) { return std::isfinite(r.max); }

bool inRange(const OptionRange& r, double v) {
    if (hasMin(r) && (r.minOpen ? !(v > r.min) : !(v >= r.min))) return false;
    if (hasMax(r) && (r.maxOpen ? !(v < r.max) : !(v <= r.max))) return false;
    return true;
}

// The range in words, for errors: "greater than 0", "between 1 and 100000".
std::string rangeWords(const OptionRange& r) {
    const std::string lo = shortest(r.min), hi = shortest(r.max);
    if (hasMin(r) && hasMax(r)) {
        if (!r.minOpen && !r.maxOpen) return "between " + lo + " and " + hi;
        return (r.minOpen ? "greater than " + lo : lo + " or more") + " and " +
               (r.maxOpen ? "below " + hi : "at most " + hi);
    }
    if (hasMin(r)) return r.minOpen ? "greater than " + lo : lo + " or more";
    if (hasMax(r)) return r.maxOpen ? "below " + hi : hi + " or less";
    return "";
}

// The range in symbols, for the docs' table: "> 0", "0 to 1", "> 0 and < 2".
std::string rangeSymbols(const OptionRange& r) {
    const std::string lo = shortest(r.min), hi = shortest(r.max);
    std::string a = hasMin(r) ? (r.minOpen ? "> " : "≥ ") + lo : "";
    std::string b = hasMax(r) ? (r.maxOpen ? "< " : "≤ ") + hi : "";
    if (hasMin(r) && hasMax(r) && !r.minOpen && !r.maxOpen) return lo + " to " + hi;
    if (!a.empty() && !b.empty()) return a + " and " + b;
    return a + b;
}

Error bad(const std::string& where, std::string message) {
    return makeError(ErrorKind::BadInput, where, std::move(message));
}

// One float component: finite, finite as a float, and in range once converted.
// The value is quoted as parsed (1e+40 whether written 1e40 or 1e+40), so that a file and the
// command line give the same message for it.
Status checkNumber(const OptionRange& range, double v, const std::string& where) {
    const std::string written = shortest(v);
    if (!std::isfinite(v)) return bad(where, "expected a finite number, got " + written);
    const float f = float(v);
    if (!std::isfinite(f))
        return bad(where, "is too large for single precision, got " + written);
    if (!inRange(range, double(f)))
        return bad(where, "must be " + rangeWords(range) + ", got " + written +
                              (f == 0.0f && v != 0.0 ? " (0 as a float)" : ""));
    // In range or not, a number that is not 0 must not become 0 or a subnormal float, which
    // keeps fewer digits.
    if (v != 0.0 && !std::isnormal(f))
        return bad(where, "is too small for single precision (other than 0, at least 1.2e-38 "
                          "in size), got " + written);
    return {};
}

template <class T> bool readWhole(std::string_view text, T& out) {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return ec == std::errc() && ptr == end && !text.empty();
}

} // namespace

std::span<const Option> optionTable() { return table(); }

const Option* findOptionByKey(std::string_view key) {
    for (const Option& o : table())
        if (!o.key.empty() && o.key == key) return &o;
    return nullptr;
}

const Option* findOptionByName(std::string_view name) {
    for (const Option& o : table())
        if (o.name == name || (!o.alias.empty() && o.alias == name)) return &o;
    return nullptr;
}

Result<OptionValue> parseOptionText(const Option& option, std::string_view text,
                                    const std::string& where) {
    switch (option.kind) {
    case OptionKind::Number: {
        double v = 0;
        if (!readWhole(text, v)) return bad(where, "expected a number, got " + quoted(text));
        return OptionValue(v);
    }
    case OptionKind::WholeNumber: {
        std::int64_t v = 0;
        if (!readWhole(text, v)) return bad(where, "expected an integer, got " + quoted(text));
        return OptionValue(v);
    }
    case OptionKind::Bool:
        if (text == "true" || text == "1" || text == "yes") return OptionValue(true);
        if (text == "false" || text == "0" || text == "no") return OptionValue(false);
        return bad(where, "expected true or false, got " + quoted(text));
    case OptionKind::Vec3: {
        glm::dvec3 v(0.0);
        std::size_t start = 0;
        for (int i = 0; i < 3; ++i) {
            const std::size_t comma = i < 2 ? text.find(',', start) : text.size();
            if (comma == std::string_view::npos ||
                !readWhole(text.substr(start, comma - start), v[i]))
                return bad(where, "expected three numbers x,y,z, got " + quoted(text));
            start = comma + 1;
        }
        return OptionValue(v);
    }
    case OptionKind::Choice:
    case OptionKind::Text:
        return OptionValue(std::string(text));
    }
    return bad(where, "unreadable value");
}

Status assignOption(const Option& option, const OptionValue& value, const std::string& where,
                    OptionTarget target) {
    switch (option.kind) {
    case OptionKind::Number:
        RUBBLE_ASSERT(std::holds_alternative<double>(value));
        RUBBLE_TRY(checkNumber(option.range, std::get<double>(value), where));
        break;
    case OptionKind::WholeNumber: {
        RUBBLE_ASSERT(std::holds_alternative<std::int64_t>(value));
        const std::int64_t v = std::get<std::int64_t>(value);
        if (!inRange(option.range, double(v)))
            return bad(where, "must be " + rangeWords(option.range) + ", got " + std::to_string(v));
        break;
    }
    case OptionKind::Vec3:
        RUBBLE_ASSERT(std::holds_alternative<glm::dvec3>(value));
        for (int i = 0; i < 3; ++i) {
            const double c = std::get<glm::dvec3>(value)[i];
            RUBBLE_TRY(checkNumber(option.range, c, where + "[" + std::to_string(i) + "]"));
        }
        break;
    case OptionKind::Choice: {
        RUBBLE_ASSERT(std::holds_alternative<std::string>(value));
        const std::string& s = std::get<std::string>(value);
        bool known = false;
        for (std::string_view c : option.choices) known = known || c == s;
        if (!known)
            return bad(where, "unknown value " + quoted(s) + " (expected " +
                                  listText(option.choices, " or ") + ")");
        break;
    }
    case OptionKind::Bool:
        RUBBLE_ASSERT(std::holds_alternative<bool>(value));
        break;
    case OptionKind::Text:
        RUBBLE_ASSERT(std::holds_alternative<std::string>(value));
        break;
    }
    option.store(target, value);
    return {};
}

Status assignOptionText(const Option& option, std::string_view text, const std::string& where,
                        OptionTarget target) {
    Result<OptionValue> v = parseOptionText(option, text, where);
    RUBBLE_TRY(v);
    return assignOption(option, *v, where, target);
}

std::string optionText(const OptionValue& value) {
    struct Visit {
        std::string operator()(double v) const { return shortestFloat(v); }
        std::string operator()(std::int64_t v) const { return std::to_string(v); }
        std::string operator()(bool v) const { return v ? "true" : "false"; }
        std::string operator()(const std::string& v) const { return v; }
        std::string operator()(const glm::dvec3& v) const {
            return shortestFloat(v.x) + "," + shortestFloat(v.y) + "," + shortestFloat(v.z);
        }
    };
    return std::visit(Visit{}, value);
}

std::string optionJson(const OptionValue& value) {
    if (const auto* s = std::get_if<std::string>(&value)) return quoted(*s);
    if (const auto* v = std::get_if<glm::dvec3>(&value))
        return enclose("[", shortestFloat(v->x) + ", " + shortestFloat(v->y) + ", " +
                                shortestFloat(v->z), "]");
    return optionText(value);
}

std::string optionDefaultText(const Option& option) {
    const std::optional<OptionValue> v = option.load(SimulationOptions{}, RunOptions{});
    return v ? optionText(*v) : std::string(option.unsetText);
}

std::string optionAllowedText(const Option& option) {
    const std::string unit = option.unit.empty() ? "" : ", " + std::string(option.unit);
    const std::string range = rangeSymbols(option.range);
    switch (option.kind) {
    case OptionKind::Number:
    case OptionKind::Vec3:
        return (range.empty() ? "finite" : range) + unit;
    case OptionKind::WholeNumber:
        return "integer " + std::string(range.find(" to ") != std::string::npos ? "from " : "") +
               range;
    case OptionKind::Choice:
        return listText(option.choices, ", ", true);
    case OptionKind::Bool:
        return "boolean";
    case OptionKind::Text:
        return "text";
    }
    return "";
}

std::string optionTypeName(const Option& option) {
    switch (option.kind) {
    case OptionKind::Number:
        return "FLOAT";
    case OptionKind::WholeNumber:
        return "INT";
    case OptionKind::Vec3:
        return "X,Y,Z";
    case OptionKind::Choice:
        return listText(option.choices, "|", false, "|");
    case OptionKind::Bool:
        // A run option's flag stands alone; a scene option's flag overrides the file both ways.
        return option.scope == OptionScope::Simulation ? "true|false" : "";
    case OptionKind::Text:
        return "TEXT";
    }
    return "";
}

std::string optionFlagHelp(const Option& option) {
    std::string help(option.help);
    if (!option.unit.empty()) help += ", " + std::string(option.unit);
    if (option.kind == OptionKind::Number || option.kind == OptionKind::WholeNumber) {
        const std::string range = rangeSymbols(option.range);
        if (!range.empty()) help += ": " + range;
    }
    if (option.scope == OptionScope::Simulation)
        help += " [simulation." + std::string(option.key) + ", default " +
                optionDefaultText(option) + "]";
    return help;
}

std::string simulationOptionsMarkdown() {
    std::string md = "| key | default | allowed | meaning | command line |\n"
                     "| --- | --- | --- | --- | --- |\n";
    for (const Option& o : table()) {
        if (o.scope != OptionScope::Simulation) continue;
        const std::optional<OptionValue> v = o.load(SimulationOptions{}, RunOptions{});
        const std::string def = v ? code(optionJson(*v)) : std::string(o.unsetText);
        std::string cli;
        if (o.uses & kUseFlag) cli += code(enclose("--", o.name, ""));
        if (o.uses & kUseCompare) {
            cli += cli.empty() ? "" : ", ";
            cli += code(enclose("", o.name, "="));
            if (!o.alias.empty()) cli += " or " + code(enclose("", o.alias, "="));
        }
        std::string allowed = optionAllowedText(o);
        if (o.kind == OptionKind::Choice) {
            allowed.clear();
            for (std::string_view c : o.choices)
                allowed += (allowed.empty() ? "" : ", ") + code(quoted(c));
        }
        md += enclose("| `", o.key, "` | ") + def + " | " + allowed + " | " +
              std::string(o.help) + " | " + cli + " |\n";
    }
    return md;
}

Status setOptionText(std::string_view name, std::string_view text, const std::string& where,
                     SimulationOptions& simulation, RunOptions& run) {
    const Option* o = findOptionByName(name);
    if (o == nullptr || !(o->uses & kUseFlag))
        return makeError(ErrorKind::NotSupported, where, "not an option of the command line");
    return assignOptionText(*o, text, where, OptionTarget{&simulation, &run});
}

std::string compareKeysText() {
    std::vector<std::string_view> keys;
    for (const Option& o : table())
        if (o.uses & kUseCompare) keys.push_back(o.name);
    return listText(keys, " or ");
}

} // namespace rubble
