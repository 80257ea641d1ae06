// host/core/options.cpp: scene-file spellings of the option enums (include/rubble/options.h).
#include "rubble/options.h"

#include <array>
#include <utility>

namespace rubble {
namespace {

template <class E, std::size_t N>
std::string_view nameOf(const std::array<std::pair<E, std::string_view>, N>& table, E v) {
    for (const auto& [value, name] : table)
        if (value == v) return name;
    return "?";
}

template <class E, std::size_t N>
std::optional<E> valueOf(const std::array<std::pair<E, std::string_view>, N>& table,
                         std::string_view s) {
    for (const auto& [value, name] : table)
        if (name == s) return value;
    return std::nullopt;
}

constexpr std::array kIntegrators{std::pair{Integrator::Symplectic, std::string_view("symplectic")},
                                  std::pair{Integrator::Explicit, std::string_view("explicit")}};
constexpr std::array kBackends{std::pair{Backend::Cpu, std::string_view("cpu")},
                               std::pair{Backend::OpenCl, std::string_view("opencl")}};
constexpr std::array kMethods{std::pair{CollisionMethod::Sat, std::string_view("sat")},
                              std::pair{CollisionMethod::Particles, std::string_view("particles")}};
constexpr std::array kSolvers{std::pair{SolverType::Pgs, std::string_view("pgs")},
                              std::pair{SolverType::Jacobi, std::string_view("jacobi")},
                              std::pair{SolverType::LcpJacobi, std::string_view("lcp-jacobi")},
                              std::pair{SolverType::Lemke, std::string_view("lemke")}};
constexpr std::array kCouplings{std::pair{Coupling::OneWay, std::string_view("one-way")},
                                std::pair{Coupling::TwoWay, std::string_view("two-way")}};

} // namespace

std::string_view toString(Integrator v) { return nameOf(kIntegrators, v); }
std::string_view toString(Backend v) { return nameOf(kBackends, v); }
std::string_view toString(CollisionMethod v) { return nameOf(kMethods, v); }
std::string_view toString(SolverType v) { return nameOf(kSolvers, v); }
std::string_view toString(Coupling v) { return nameOf(kCouplings, v); }

std::optional<Integrator> parseIntegrator(std::string_view s) { return valueOf(kIntegrators, s); }
std::optional<Backend> parseBackend(std::string_view s) { return valueOf(kBackends, s); }
std::optional<CollisionMethod> parseCollisionMethod(std::string_view s) {
    return valueOf(kMethods, s);
}
std::optional<SolverType> parseSolverType(std::string_view s) { return valueOf(kSolvers, s); }
std::optional<Coupling> parseCoupling(std::string_view s) { return valueOf(kCouplings, s); }

} // namespace rubble
