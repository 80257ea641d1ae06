// host/dynamics/pgs.h: CPU stage 6, solvePgs: projected Gauss-Seidel over joint and contact rows
// (sequential impulses with accumulated clamping and warm starting).
#pragma once

#include <span>
#include <vector>

#include "host/dynamics/contact_rows.h"
#include "host/dynamics/joints.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/options.h"

namespace rubble {

/// Stage solvePgs (Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005, and "Fast and
/// Simple Physics using Sequential Impulses", GDC 2006). Warm start: the rows' accumulated
/// impulses are applied first. Then `iterations` sweeps over the joints, then every contact's
/// normal row, then every point's pair of friction rows (bounded by this sweep's normal
/// impulses, a tall stack stands better than with each point's rows together; the pair is
/// updated from the same velocities and applied at once): lambda_new = clamp(lambda + w dlambda),
/// dlambda = m_eff (target - J v), w = relaxation; lambda_n >= 0 and |lambda_t| <= mu lambda_n;
/// only the clamped change is applied. residuals[k] is the largest |applied change| (N s) of
/// sweep k. Then, when a contact penetrates beyond the slop, the split position pass: up to the
/// same number of sweeps over the normal rows that push and the rows touching the bodies they
/// move, on separate pseudo-velocities that start at zero and aim at the rows' Baumgarte speeds
/// (lambda_push >= 0), so that pushing bodies apart adds no energy; PgsSolver::solvePositions
/// moves the bodies by dt times them.
/// reads: rows, joints, bodies   writes: bodies' velocities and push, impulses, residuals
void solvePgs(ContactRows& contacts, std::span<Joint> joints, SolverBodies& bodies,
              const SolverOptions& options, std::vector<float>& residuals);

/// One sweep of the contact rows; returns the largest |applied impulse change|, N s.
float solveContactSweep(ContactRows& contacts, SolverBodies& bodies, float relaxation);

/// Applies the contacts' accumulated impulses (warm start). writes: bodies' velocities
void warmStartContacts(const ContactRows& contacts, SolverBodies& bodies);

/// The split position pass; returns false (and leaves bodies.push untouched) when no contact
/// needs it. writes: bodies.push, rows' push impulses
bool solvePushes(ContactRows& contacts, SolverBodies& bodies, int iterations, float relaxation);

} // namespace rubble
