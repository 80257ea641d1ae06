// host/core/options.cpp: scene-file spellings of the option enums (include/rubble/options.h).
#include "rubble/options.h"

#include <cstddef>

namespace rubble {
namespace {

// Each enum's spellings, indexed by its value (the enums count from 0 in declaration order).
constexpr std::string_view kIntegrators[] = {"symplectic", "explicit"};
constexpr std::string_view kBackends[] = {"cpu", "opencl"};
constexpr std::string_view kMethods[] = {"sat", "particles"};
constexpr std::string_view kSolvers[] = {"pgs", "jacobi", "lcp-jacobi", "lemke",
                                         "soft-step"};
constexpr std::string_view kCouplings[] = {"one-way", "two-way"};
constexpr std::string_view kColorings[] = {"auto", "host", "device"};

template <class E> std::string_view nameOf(E v) {
    const std::span<const std::string_view> names = spellings<E>();
    const auto i = static_cast<std::size_t>(v);
    return i < names.size() ? names[i] : "?";
}

template <class E> std::optional<E> valueOf(std::string_view s) {
    const std::span<const std::string_view> names = spellings<E>();
    for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i] == s) return static_cast<E>(i);
    return std::nullopt;
}

} // namespace

template <> std::span<const std::string_view> spellings<Integrator>() { return kIntegrators; }
template <> std::span<const std::string_view> spellings<Backend>() { return kBackends; }
template <> std::span<const std::string_view> spellings<CollisionMethod>() { return kMethods; }
template <> std::span<const std::string_view> spellings<SolverType>() { return kSolvers; }
template <> std::span<const std::string_view> spellings<Coupling>() { return kCouplings; }
template <> std::span<const std::string_view> spellings<PgsColoring>() {
    return kColorings;
}

std::string_view toString(Integrator v) { return nameOf(v); }
std::string_view toString(Backend v) { return nameOf(v); }
std::string_view toString(CollisionMethod v) { return nameOf(v); }
std::string_view toString(SolverType v) { return nameOf(v); }
std::string_view toString(Coupling v) { return nameOf(v); }
std::string_view toString(PgsColoring v) {
    return nameOf(v);
}

PgsColoring resolvePgsColoring(PgsColoring chosen, SolverType solver) {
    if (chosen != PgsColoring::Auto) return chosen;
    return solver == SolverType::SoftStep ? PgsColoring::Device : PgsColoring::Host;
}

std::optional<Integrator> parseIntegrator(std::string_view s) { return valueOf<Integrator>(s); }
std::optional<Backend> parseBackend(std::string_view s) { return valueOf<Backend>(s); }
std::optional<CollisionMethod> parseCollisionMethod(std::string_view s) {
    return valueOf<CollisionMethod>(s);
}
std::optional<SolverType> parseSolverType(std::string_view s) { return valueOf<SolverType>(s); }
std::optional<Coupling> parseCoupling(std::string_view s) { return valueOf<Coupling>(s); }

} // namespace rubble
