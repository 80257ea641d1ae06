// host/dynamics/pgs.h: CPU stage 6, solvePgs: projected Gauss-Seidel over joint and contact rows
// (sequential impulses with accumulated clamping and warm starting).
#pragma once

#include <span>
#include <vector>

#include "host/dynamics/contact_rows.h"
#include "host/dynamics/joints.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/options.h"
#include "rubble/shared/body.h"
#include "rubble/shared/pgs_row.h"

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
/// moves the bodies by dt times them. After the sweeps, the layer pass (solveLayers). The contact
/// rows run in SweepRows' order, and without joints island by island, each island's sweeps
/// together: the same bits as the sweeps above, from the caches.
/// reads: rows, joints, bodies   writes: bodies' velocities and push, impulses, residuals
void solvePgs(ContactRows& contacts, std::span<Joint> joints, SolverBodies& bodies,
              const SolverOptions& options, std::vector<float>& residuals);

/// A contact's upper body is this many times as heavy as its lower one before the layer pass
/// takes it (solveLayers).
inline constexpr float kLayerMassRatio = RUBBLE_LAYER_MASS_RATIO;

/// The layer pass (shock propagation, Guendelman, Bridson and Fedkiw, "Nonconvex rigid bodies
/// with stacking", SIGGRAPH 2003, section 7, on velocities), after the sweeps of solvePgs: with a
/// heavy body on a light one, Gauss-Seidel passes the weight down by a fraction m_light /
/// m_heavy a sweep, so 10 sweeps leave a 1:100 stack sinking and tipping. Layers count contacts
/// up from the bodies that do not move. The rows whose upper body is kLayerMassRatio times as
/// heavy as the lower one, and the rows under a body that carries such a load, are updated once
/// more from the bottom up, each moving only its upper body (the lower one held as if it did not
/// move): what is below has stopped when what is above stops on it. Rows of bodies in joints do
/// not take part. The pass's impulses are not kept for the warm start (they are what the sweeps
/// have not yet found: the sweeps get there over the next steps). Scenes without such a pair
/// skip it. reads: rows, joints   writes: bodies' velocities, rows' layer lists
void solveLayers(ContactRows& contacts, std::span<const Joint> joints, SolverBodies& bodies);

/// Every row of `contacts` in the sweeps' order (SweepOrder).
/// reads: contacts' keys, bodies   writes: s
void orderEveryRow(const ContactRows& contacts, const SolverBodies& bodies, SweepOrder& s);

/// Copies the rows into contacts.sweep, the packed form the sweeps stream through (a point's
/// normal row in 80 bytes, its friction rows in 160, against 352 for the full rows) in the
/// sweeps' order (SweepOrder), and with `warmStart` applies the contacts' accumulated impulses in
/// the same pass.
/// reads: rows   writes: contacts.sweep, bodies' velocities (warm start)
void packContactRows(ContactRows& contacts, SolverBodies& bodies, bool warmStart);

/// One sweep of the packed contact rows [begin, end); returns the largest |applied impulse
/// change|, N s.
float solveContactSweep(SweepRows& rows, std::size_t begin, std::size_t end, SolverBodies& bodies,
                        float relaxation);

/// The sweeps' impulses back into the full rows. reads: contacts.sweep   writes: rows' impulses
void unpackContactImpulses(ContactRows& contacts);

/// The split position pass; returns false (and leaves bodies.push untouched) when no contact
/// needs it. A row that bounces (a bounce speed, and a normal impulse from the solve) aims at the
/// larger of its Baumgarte speed and its bounce's lift, which carries the bodies from the
/// contact to where the rebound has taken them by the step's end. Then the layer pass's rows
/// (solveLayers) once more, bottom up, each moving its upper body only, so that a light body
/// under a heavy one is pushed out as well. The sweeps run over packed rows in SweepRows' order
/// (contacts.pushSweep): the same bits as in ContactRows' order.
/// writes: bodies.push, rows' push targets and impulses
bool solvePushes(ContactRows& contacts, SolverBodies& bodies, int iterations, float relaxation);

/// The restitution pass, after the positions moved (as Box2D v3 applies restitution after its
/// relax iterations): the rows that bounce (bounceSpeed > 0) and stopped their bodies in this
/// step's solve (impulse > 0, so that the bodies reached the contact) give them back bounceSpeed
/// along the normal, by up to `iterations` sweeps of lambda_b = max(lambda_b + m_eff
/// (bounceSpeed - J v), -lambda) on the solved velocities (the solve's impulse and the bounce's
/// stay >= 0 together). A bounce thus leaves from the contact, not from where the step began.
/// Returns false when no row bounces. reads: rows   writes: rows' bounce impulses,
/// bodies' velocities
bool solveRestitution(ContactRows& contacts, SolverBodies& bodies, int iterations);

/// The bounce impulses into the momenta: P += lambda_b n, L += lambda_b (r x n) on b, the
/// opposite on a. reads: rows   writes: momenta
void addBounceImpulses(const ContactRows& contacts, std::span<shared::BodyMomentum> momenta);

} // namespace rubble
