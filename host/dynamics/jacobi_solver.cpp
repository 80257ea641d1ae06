// host/dynamics/jacobi_solver.cpp: the CPU twins of the device's solvers as solver stages over
// the body arrays, and the choice of a solver's stage object.
#include "host/dynamics/jacobi_solver.h"

#include <string>

#include "host/dynamics/lemke.h"
#include "host/dynamics/pgs_solver.h"
#include "host/dynamics/soft_step_solver.h"

namespace rubble {

using namespace shared;

bool JacobiSolver::wake(const SolverScene&, Bodies bodies, std::span<const BodyVelocity> approach,
                        const StepContacts& contacts, const StepParams&) {
    wakeTouched(contacts.points, approach, bodies.masses, sleep_);
    return false;
}

void JacobiSolver::buildRows(const SolverScene& scene, BodiesView bodies,
                             std::span<const BodyVelocity> approach, const StepContacts& contacts,
                             const StepParams& params) {
    JacobiState& j = jacobi_;
    buildBodyLists(contacts.points, bodies.masses, j);
    if (params.solver.warmStart)
        matchWarmStart(contacts.points, j.previous, j.warm);
    else
        j.warm.assign(contacts.points.size(), vec4(0.0f, 0.0f, 0.0f));
    buildJacobiRows(contacts.points, bodies.poses, approach, bodies.masses, scene.surfaces,
                    params.rows, j.warm, j);
}

Status JacobiSolver::solve(const SolverScene&, Bodies bodies, std::span<const BodyVelocity> before,
                           const StepContacts& contacts, const StepParams& params) {
    JacobiState& j = jacobi_;
    solveJacobi(j, before, bodies.masses, bodies.poses, bodies.velocities, params.solver.iterations,
                params.jacobiRelaxation);
    if (params.solver.warmStart) rememberImpulses(contacts.points, j.rows, j.previous);
    return {};
}

void JacobiSolver::finishSolve(Bodies bodies, std::span<const BodyVelocity> before,
                               const StepContacts& contacts, const StepParams& params) {
    JacobiState& j = jacobi_;
    gatherJacobi(j.rows, j, before, bodies.masses, bodies.poses, bodies.velocities);
    if (params.solver.warmStart) rememberImpulses(contacts.points, j.rows, j.previous);
}

std::uint32_t JacobiSolver::sleep(const SolverScene&, Bodies bodies, const StepContacts&,
                                  const StepParams& params) {
    return sleepBodies(jacobi_.rows, bodies.masses, bodies.velocities, bodies.momenta, params.dt,
                       sleep_)
        .asleep;
}

void JacobiSolver::bodiesChanged(std::span<const std::uint32_t>, BodiesView) {
    jacobi_.previous.clear();
    sleep_ = BodySleepState{};
}

namespace {

Error tooLarge(const StepParams& params, const char* solver, std::size_t rows, std::size_t limit,
               const char* instead) {
    return makeError(ErrorKind::NotSupported, "step " + std::to_string(params.step + 1),
                     std::string("the ") + solver + " solver takes at most " +
                         std::to_string(limit) + " rows; this step has " + std::to_string(rows) +
                         " (" + instead + ")");
}

} // namespace

Status LcpJacobiSolver::solve(const SolverScene& scene, Bodies bodies,
                              std::span<const BodyVelocity> before, const StepContacts& contacts,
                              const StepParams& params) {
    DenseLcp& p = dense_;
    const std::uint32_t stride = lcpStride(scene.surfaces, bodies.masses);
    const std::size_t rows = jacobi_.rows.size() * stride;
    if (rows > kLcpMaxRows)
        return tooLarge(params, "lcp-jacobi", rows, kLcpMaxRows, "jacobi and pgs take any number");
    buildLcpRows(jacobi_.rows, before, bodies.masses, bodies.poses, stride, p);
    assembleDelassus(p);
    scaleLcpRows(p);
    solveLcpJacobi(p, params.solver.iterations, params.lcpJacobiRelaxation);
    storeLcpImpulses(p, jacobi_.rows);
    finishSolve(bodies, before, contacts, params);
    return {};
}

Status LemkeSolver::solve(const SolverScene& scene, Bodies bodies,
                          std::span<const BodyVelocity> before, const StepContacts& contacts,
                          const StepParams& params) {
    DenseLcp& p = dense_;
    const std::span<const ContactRow> rows = jacobi_.rows;
    for (const ContactRow& r : rows)
        if (r.friction > 0.0f)
            return makeError(ErrorKind::NotSupported, "step " + std::to_string(params.step + 1),
                             "the lemke solver takes frictionless contacts only; bodies " +
                                 scene.names[r.a] + " and " + scene.names[r.b] +
                                 " touch with friction " + std::to_string(r.friction));
    if (rows.size() > kLemkeMaxRows)
        return tooLarge(params, "lemke", rows.size(), kLemkeMaxRows,
                        "lcp-jacobi, jacobi and pgs take more");
    buildLcpRows(rows, before, bodies.masses, bodies.poses, 1u, p);
    assembleDelassus(p);
    std::vector<double> m, q;
    lcpNormalProblem(p, m, q);
    Result<LemkeSolution> solved = solveLemke(m, q);
    if (!solved) {
        Error e = solved.error();
        e.where = "step " + std::to_string(params.step + 1) + ": " + e.where;
        return e;
    }
    for (std::size_t i = 0; i < p.lambda.size(); ++i) p.lambda[i] = float(solved->z[i]);
    p.residuals.clear();
    storeLcpImpulses(p, jacobi_.rows);
    finishSolve(bodies, before, contacts, params);
    return {};
}

std::unique_ptr<ContactSolver> makeContactSolver(SolverType type) {
    switch (type) {
    case SolverType::Pgs:
        return std::make_unique<PgsSolver>();
    case SolverType::Jacobi:
        return std::make_unique<JacobiSolver>();
    case SolverType::LcpJacobi:
        return std::make_unique<LcpJacobiSolver>();
    case SolverType::Lemke:
        return std::make_unique<LemkeSolver>();
    case SolverType::SoftStep:
        return std::make_unique<SoftStepSolver>();
    }
    return std::make_unique<PgsSolver>();
}

} // namespace rubble
