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
/// impulses are applied first. Then `iterations` sweeps over the joints, then the contacts
/// (friction rows before the normal row of each point): lambda_new = clamp(lambda + w dlambda),
/// dlambda = m_eff (target - J v), w = relaxation; lambda_n >= 0 and |lambda_t| <= mu lambda_n;
/// only the clamped change is applied. residuals[k] is the largest |applied change| (N s) of
/// sweep k.
/// reads: rows, joints, bodies   writes: bodies' velocities, impulses, residuals
void solvePgs(std::span<ContactRow> contacts, std::span<Joint> joints, SolverBodies& bodies,
              const SolverOptions& options, std::vector<float>& residuals);

/// One sweep of the contact rows; returns the largest |applied impulse change|, N s.
float solveContactSweep(std::span<ContactRow> contacts, SolverBodies& bodies, float relaxation);

/// Applies the contacts' accumulated impulses (warm start). writes: bodies' velocities
void warmStartContacts(std::span<const ContactRow> contacts, SolverBodies& bodies);

} // namespace rubble
