// host/gpu/traffic.cpp: bytes per launch of each kernel (counted from kernels/*.cl) and the
// measured copy bandwidths they are set against (`rubble devices --bandwidth`).
#include "host/gpu/traffic.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <vector>

#include "host/gpu/buffer.h"
#include "host/gpu/context.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/hull_contact.h"
#include "rubble/shared/particle.h"
#include "rubble/shared/pgs_joint.h"
#include "rubble/shared/pgs_row.h"

namespace rubble::gpu {
namespace {

using shared::BodyForce;
using shared::BodyMass;
using shared::BodyMomentum;
using shared::BodyPose;
using shared::BodyVelocity;
using shared::ContactRow;
using shared::JacobiBody;
using shared::Particle;
using shared::ParticleContact;

constexpr std::uint64_t kWord = 4, kVec = 16;

// Records a binary search over a sorted set reads from memory: its top levels are the same for
// every work-item and stay in cache, so it counts as four, as particlePairs' search does.
constexpr std::uint64_t kSearchReads = 4;

} // namespace

std::uint64_t kernelBytes(KernelId id, const TrafficCounts& n) {
    // Body list entries: one per side of a contact (an upper bound: the static side has none).
    const std::uint64_t entries = 2 * n.contacts;
    // The radix sort's digit-major histogram (and its scan), read or written whole by each pass.
    const std::uint64_t kHistogram = RUBBLE_SORT_BUCKETS * n.sortItems * kWord;
    // SAT: a box, the broad-phase flags and a pair record.
    constexpr std::uint64_t kBox = sizeof(shared::BodyBox), kPair = sizeof(shared::BodyPairRecord);
    switch (id) {
    case KernelId::IntegrateVelocities: // flags, forces, masses, momenta r/w, pose, velocity r/w,
                                        // the velocity before the forces
        return n.bodies * (kWord + sizeof(BodyForce) + sizeof(BodyMass) + 2 * sizeof(BodyMomentum) +
                           sizeof(BodyPose) + 3 * sizeof(BodyVelocity));
    case KernelId::AbsorbVelocityChange: // momenta r/w, before, after, masses, pose
        return n.bodies * (2 * sizeof(BodyMomentum) + 2 * sizeof(BodyVelocity) + sizeof(BodyMass) +
                           sizeof(BodyPose));
    case KernelId::IntegratePositions: // flags, masses, momenta, pose r/w, velocity r/w
        return n.bodies * (kWord + sizeof(BodyMass) + sizeof(BodyMomentum) + 2 * sizeof(BodyPose) +
                           2 * sizeof(BodyVelocity));
    case KernelId::SumBodyEnergy: // masses, velocities, momenta, pose; energy written
        return n.bodies * (sizeof(BodyMass) + sizeof(BodyVelocity) + sizeof(BodyMomentum) +
                           sizeof(BodyPose) + kWord);
    case KernelId::TransformParticles: // records, world; each body's flags and pose
        return n.particles * (sizeof(Particle) + kVec) + n.bodies * (kWord + sizeof(BodyPose));
    case KernelId::ComputeCellKeys: // world; key and value written
        return n.particles * (kVec + 2 * kWord);
    case KernelId::SortHistogram: // keys; the histogram
        return n.particles * kWord + kHistogram;
    case KernelId::SortScatter: // keys and values read and written; the offsets
        return n.particles * 4 * kWord + kHistogram;
    case KernelId::FindCellRanges: // keys (and the previous), order, world, body; sorted copies
        return n.particles * (2 * kWord + kWord + kVec + kWord + kVec + kWord) + n.bodies * kWord +
               (n.cells + 1) * kWord;
    case KernelId::CollideParticles: // sorted world, tags, order; the cell table; contacts
        return n.particles * (kVec + 2 * kWord) + (n.cells + 1) * kWord +
               n.contacts * (sizeof(ParticleContact) + 2 * kWord);
    case KernelId::CountBodyContacts: // a and b; flags and counters of each body
        return n.contacts * 2 * kWord + n.bodies * 3 * kWord;
    case KernelId::FillBodyLists: // a and b, list entries; flags and cursors
        return n.contacts * 2 * kWord + entries * kWord + n.bodies * 3 * kWord;
    case KernelId::SortBodyLists: // starts; entries read and written
        return (n.bodies + 1) * kWord + entries * 2 * kWord;
    case KernelId::LinkPrevious: // particleA, next; the chain heads
        return n.previous * 3 * kWord;
    case KernelId::PrepareJacobiBodies: // masses, flags, pose; JacobiBody
        return n.bodies * (sizeof(BodyMass) + kWord + sizeof(BodyPose) + sizeof(JacobiBody));
    case KernelId::BuildJacobiRows: // contact, chain walk, last impulses, row; per body state
        return n.contacts * (sizeof(ParticleContact) + 2 * kWord + kVec + sizeof(ParticleContact) +
                             sizeof(ContactRow)) +
               n.bodies *
                   (sizeof(BodyPose) + sizeof(BodyVelocity) + sizeof(JacobiBody) + kVec + kWord);
    case KernelId::SolveJacobiRows: // row, lambda and impulse written; velocities
        return n.contacts * (sizeof(ContactRow) + 2 * kVec) + n.bodies * sizeof(BodyVelocity);
    case KernelId::GatherJacobi: // entry, impulse, arm; per body start, before, JacobiBody,
                                 // flags, velocity written
        return entries * (kWord + 2 * kVec) +
               n.bodies * (2 * kWord + 2 * sizeof(BodyVelocity) + sizeof(JacobiBody) + kWord);
    case KernelId::GatherJacobiRows: // entry, row, arm written; per body as GatherJacobi
        return entries * (kWord + sizeof(ContactRow) + kVec) +
               n.bodies * (2 * kWord + 2 * sizeof(BodyVelocity) + sizeof(JacobiBody) + kWord);
    case KernelId::WakeTouched: // a and b of each contact; their flags and approach velocities
        return n.contacts * (2 * kWord + 2 * kWord + 2 * sizeof(BodyVelocity));
    case KernelId::MarkRestless: // a and b of each row; flags, velocities, restless marks
        return n.contacts * 2 * kWord + n.bodies * (2 * kWord + sizeof(BodyVelocity));
    case KernelId::SleepBodies: // flags, timers, marks; velocities and momenta of sleepers
        return n.bodies * (4 * kWord + sizeof(BodyVelocity) + sizeof(BodyMomentum));
    case KernelId::ComputeAabbs: // shape index, flags, pose, velocity; box, spin, flags written
        return n.bodies * (2 * kWord + sizeof(BodyPose) + sizeof(BodyVelocity) + kBox + 2 * kWord);
    case KernelId::GridBounds: // box and flags of each body; one partial per work-item
        return n.bodies * (kBox + kWord) + n.sortItems * sizeof(shared::GridPartial);
    case KernelId::GridSetup: // the partials; the grid
        return n.sortItems * sizeof(shared::GridPartial) + sizeof(shared::GridParams);
    case KernelId::GridEntries: // flags and box of each body; entries (key, value), large list
        return n.bodies * (kWord + kBox) + n.gridEntries * 2 * kWord + n.largeBodies * 2 * kWord +
               sizeof(shared::GridParams);
    case KernelId::GatherCellBoxes: // value, the body's box; the box written
        return n.gridEntries * (kWord + 2 * kBox);
    case KernelId::FindCellPairs: // key, value and box per entry; pairs
        return n.gridEntries * (2 * kWord + kBox) + n.pairs * kPair;
    case KernelId::FindLargePairs: // flags and box of each body, the planes and large lists
        return (n.bodies + n.planes + n.largeBodies) * (kWord + kBox) +
               (n.planes + n.largeBodies) * kWord + n.pairs * kPair;
    case KernelId::CountPairs: // pairs; counters read and written
        return n.pairs * kPair + n.bodies * 2 * kWord;
    case KernelId::PlacePairs: // pairs read and written; cursors read and written
        return n.pairs * 2 * kPair + n.bodies * 2 * kWord;
    case KernelId::SortPairLists: // starts; pairs read and written
        return (n.bodies + 1) * kWord + n.pairs * 2 * kPair;
    case KernelId::CollideShapes: // per pair: the pair, last step's pair and cache, both bodies'
                                  // shape index, pose, velocity, spin; manifold and cache written
        return n.pairs * (kPair + kPair + sizeof(shared::PairCache) +
                          2 * (kWord + sizeof(BodyPose) + sizeof(BodyVelocity) + kWord) +
                          sizeof(shared::ContactManifold) + sizeof(shared::PairCache));
    case KernelId::SummarizePairs: // pair, the manifold's count and depths, both bodies'
        // inverse mass (a JacobiBody row), the summary and the kept count written
        return n.pairs * (kPair + 5 * kWord + 2 * kVec + 2 * kWord);
    case KernelId::ApplyPushes: // status, the JacobiBody row, push velocity, momentum, mass,
        // pose read and written, velocity written
        return n.bodies * (kVec + sizeof(BodyVelocity) + sizeof(BodyMomentum) + sizeof(BodyMass) +
                           2 * sizeof(BodyPose) + sizeof(BodyVelocity));
    case KernelId::WakeTouchedPairs: // the manifold's count and pair; both flags and approach
        // velocities
        return n.pairs * (kWord + kPair + 2 * kWord + 2 * sizeof(BodyVelocity));
    case KernelId::ContactKeys: // per contact and pass: its place in the last pass's order, the
        // contact; key and value written
        return n.contacts * (kWord + sizeof(ParticleContact) + 2 * kWord);
    case KernelId::PermuteContacts: // per contact: its place, the contact read and written
        return n.contacts * (kWord + 2 * sizeof(ParticleContact));
    case KernelId::MarkRestlessPairs: // the manifold's count, pair, both flags and velocities,
        // the marks
        return n.pairs * (kWord + kPair + 2 * kWord + 2 * sizeof(BodyVelocity) + 2 * kWord);
    case KernelId::ParticlePairs: // per contact: the contact, its pair, manifold, key and last
        // step's place written, and the keys its search reads among last step's near the place
        // the contact would have if the two steps were spread alike (counted as four)
        return n.contacts * (sizeof(ParticleContact) + kPair + sizeof(shared::ContactManifold) +
                             5 * sizeof(shared::ParticleContactKey) + kWord);
    case KernelId::MarkStillPairs: // per kept entry: the pair, its impulse count, both bodies'
        // inverse mass, a search of this step's pairs (an upper bound: every entry still and
        // holding impulses), the mark written; each chunk's count
        return n.kept * (kPair + kWord + 2 * kWord + kSearchReads * kPair + kWord) +
               n.sortItems * kWord;
    case KernelId::PlaceStillPairs: // per kept entry: the mark read, the place written; the
        // chunks' starts
        return n.kept * 2 * kWord + (n.sortItems + 2) * kWord;
    case KernelId::CarryStillPairs: // per kept entry its mark; per carried one: its place, a
        // search of the other run and that entry's place, its pair, impulse count and start and
        // up to four impulses read and written
        return n.kept * kWord +
               n.carried * (2 * kWord + kSearchReads * kPair +
                            2 * (kPair + 2 * kWord + 4 * sizeof(shared::PgsImpulse)));
    case KernelId::WakeStillPairs: // per kept entry: its impulse count, its pair, both bodies'
        // flags and restless words (an upper bound: every entry holds impulses)
        return n.kept * (kWord + kPair + 4 * kWord);
    case KernelId::PrepareJoints: // per joint: the joint, both bodies' poses and JacobiBody
        // rows, its row read (warm start) and written
        return n.joints * (sizeof(shared::PgsJoint) + 2 * sizeof(BodyPose) +
                           2 * sizeof(JacobiBody) + 2 * sizeof(shared::PgsJointRow));
    case KernelId::ProjectJointGroups: { // one iteration (the kernel repeats until the joints
        // hold): per group its record; per member its index, joint and both bodies' masses, flags
        // and poses; per row the row written and read, its solution, both sides' position and
        // rotation deltas and poses read and written (an upper bound: a body once per row); the
        // lower triangle of each matrix written and read
        const std::uint64_t side = 4 * kVec + 2 * sizeof(BodyPose);
        return n.directGroups * sizeof(shared::JointGroup) +
               n.directMembers * (kWord + sizeof(shared::PgsJoint) +
                                  2 * (sizeof(BodyMass) + kWord + sizeof(BodyPose))) +
               n.directRows * (2 * sizeof(shared::JointPositionRow) + 2 * n.jointReal + 2 * side) +
               n.directMatrix * n.jointReal;
    }
    case KernelId::JointVelocities: // per jointed body: its index, mass, flags, pose, momentum;
        // its velocity written
        return n.jointBodies * (2 * kWord + sizeof(BodyMass) + sizeof(BodyPose) +
                                sizeof(BodyMomentum) + sizeof(BodyVelocity));
    case KernelId::MarkRestlessJoints: // per joint: the joint, both bodies' flags, velocities
        // and restless marks
        return n.joints * (sizeof(shared::PgsJoint) + 2 * (2 * kWord + sizeof(BodyVelocity)));
    case KernelId::VoteJointGroups: // per jointed body: its index and group, flags, slow time,
        // restless word, velocity, its group's vote
        return n.jointBodies * (6 * kWord + sizeof(BodyVelocity));
    case KernelId::HoldJointGroups: // per jointed body: its index, group, the group's vote, the
        // restless word
        return n.jointBodies * 4 * kWord;
    case KernelId::WakeJointGroups: // per jointed body: its index, group, flags and the group's
        // vote; a woken one's flags, slow time and restless word written (an upper bound)
        return n.jointBodies * 7 * kWord;
    case KernelId::PrepareIslands: // per body: flags; slow time, group, asleep word written
        return n.bodies * 4 * kWord;
    case KernelId::MarkIslandWakeBodies: // per body: flags, mass, approach velocity, radius,
        // asleep word, group, restless word written, its group's marks
        return n.bodies * (sizeof(BodyMass) + sizeof(BodyVelocity) + 6 * kWord);
    case KernelId::MarkIslandWakePairs: // per pair: its pair, summary and manifold count; both
        // bodies' flags, masses, restless words, groups and marks
        return n.pairs * (kPair + 2 * kWord + 2 * (sizeof(BodyMass) + 4 * kWord));
    case KernelId::MarkIslandWakeJoints: // per joint: the joint; both bodies as for a pair
        return n.joints * (sizeof(shared::PgsJoint) + 2 * (sizeof(BodyMass) + 4 * kWord));
    case KernelId::WakeIslandBodies: // per body: mass, group, its own and its group's marks,
        // flags read and written
        return n.bodies * (sizeof(BodyMass) + 5 * kWord);
    case KernelId::MeasureIslandBodies: // per body: flags, mass, velocity, radius, asleep word,
        // group, slow time read and written, restless word, label, its group's first member, the
        // root's words written
        return n.bodies * (sizeof(BodyMass) + sizeof(BodyVelocity) + 10 * kWord);
    case KernelId::HookIslandGroups: // per body: its group, the group's first member, its label
        return n.bodies * 3 * kWord;
    case KernelId::UniteIslandPairs: // per pair: its summary and pair; both bodies' flags,
        // masses, velocities and labels (a root two links away: an upper bound for piles)
        return n.pairs *
               (kWord + kPair + 2 * (kWord + sizeof(BodyMass) + sizeof(BodyVelocity) + 2 * kWord));
    case KernelId::UniteIslandJoints: // per joint: the joint; both bodies' masses and labels
        return n.joints * (sizeof(shared::PgsJoint) + 2 * (sizeof(BodyMass) + 2 * kWord));
    case KernelId::GatherIslands: // per body: flags, mass, slow time, restless word, labels to
        // the root, the root written; the root's words
        return n.bodies * (sizeof(BodyMass) + 8 * kWord);
    case KernelId::SleepIslands: // per body: mass, root, the root's words, flags, slow time,
        // group and asleep word written; velocity and momentum zeroed (an upper bound)
        return n.bodies *
               (sizeof(BodyMass) + 9 * kWord + sizeof(BodyVelocity) + sizeof(BodyMomentum));
    default:
        return 0;
    }
}

namespace {

double secondsOf(std::vector<double>& times) {
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

template <class F> Result<double> medianSeconds(int repeats, F&& once) {
    std::vector<double> times;
    for (int i = 0; i < repeats; ++i) {
        const auto start = std::chrono::steady_clock::now();
        RUBBLE_TRY(once());
        times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return secondsOf(times);
}

} // namespace

Result<Bandwidth> measureBandwidth(const Context& c, std::uint64_t bytes, int repeats) {
    Bandwidth b;
    b.bytes = bytes;
    repeats = std::max(repeats, 1);
    Buffer from, to;
    RUBBLE_TRY(from.reserve(c.context(), bytes));
    RUBBLE_TRY(to.reserve(c.context(), bytes));
    // Touch both once, so that first-use page faults are not timed.
    RUBBLE_TRY(fill(c, from, 1u, bytes));
    RUBBLE_TRY(fill(c, to, 2u, bytes));
    std::vector<std::uint8_t> host(bytes, 3), back(bytes, 4);
    cl_command_queue q = c.queue();
    auto copy = [&]() -> Status {
        RUBBLE_CL_CHECK(
            clEnqueueCopyBuffer(q, from.mem(), to.mem(), 0, 0, bytes, 0, nullptr, nullptr));
        RUBBLE_CL_CHECK(clFinish(q));
        return {};
    };
    auto write = [&]() -> Status {
        RUBBLE_CL_CHECK(clEnqueueWriteBuffer(q, from.mem(), CL_TRUE, 0, bytes, host.data(), 0,
                                             nullptr, nullptr));
        return {};
    };
    auto read = [&]() -> Status {
        RUBBLE_CL_CHECK(
            clEnqueueReadBuffer(q, to.mem(), CL_TRUE, 0, bytes, back.data(), 0, nullptr, nullptr));
        return {};
    };
    auto memcpyOnce = [&]() -> Status {
        std::memcpy(back.data(), host.data(), bytes);
        // Keep the copy observable, so that it is not optimised away.
        host[back[bytes / 2] % bytes] ^= 1u;
        return {};
    };
    const double total = double(bytes);
    for (int warm = 0; warm < 2; ++warm) {
        RUBBLE_TRY(copy());
        RUBBLE_TRY(write());
        RUBBLE_TRY(read());
        RUBBLE_TRY(memcpyOnce());
    }
    Result<double> t = medianSeconds(repeats, copy);
    RUBBLE_TRY(t);
    b.deviceCopy = 2 * total / *t;
    t = medianSeconds(repeats, write);
    RUBBLE_TRY(t);
    b.hostToDevice = total / *t;
    t = medianSeconds(repeats, read);
    RUBBLE_TRY(t);
    b.deviceToHost = total / *t;
    t = medianSeconds(repeats, memcpyOnce);
    RUBBLE_TRY(t);
    b.hostMemcpy = 2 * total / *t;
    return b;
}

} // namespace rubble::gpu
