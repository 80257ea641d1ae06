// tests/gpu/device_cases_test.cpp: the physics cases of tests/support/physics_cases.h on the
// OpenCL backend (particles and Jacobi), with the closed forms the CPU reference meets in
// tests/physics.
#include <cstdio>
#include <map>
#include <string>

#include "gpu_fixture.h"
#include "host/gpu/traffic.h"
#include "support/physics_cases.h"

namespace rubble {
namespace {

class DeviceCases : public test::GpuTest {};

// The kernels integrate orientations with the same exponential map (rubble/shared/math.h).
TEST_F(DeviceCases, SymplecticSpinTurnsByOmegaTimesT) {
    World w = deviceWorld(test::spinScene("symplectic", test::kDeviceSimulation));
    test::expectSpinTurnsByOmegaTimesT(w);
}

TEST_F(DeviceCases, ExplicitSpinTurnsByOmegaTimesT) {
    World w = deviceWorld(test::spinScene("explicit", test::kDeviceSimulation));
    test::expectSpinTurnsByOmegaTimesT(w);
}

// The device's rows bounce at e times the approach before the step's gravity (as the CPU's), but
// from where the particles first overlap the floor (3.8 cm deep here: particles find no contact
// ahead of time), with the Baumgarte bias lifting the ball out: the rebound keeps e^2 of the
// drop height within 1 cm; the approach taken after gravity would overshoot it by several
// centimetres.
TEST_F(DeviceCases, ElasticBallReboundsToItsDropHeight) {
    World w = deviceWorld(test::dropScene(1.0f, test::kDeviceSimulation));
    test::expectReboundHeight(w, 1.0f, 0.01f, 0.05f);
}
TEST_F(DeviceCases, HalfElasticBallReboundsToAQuarterOfItsDropHeight) {
    World w = deviceWorld(test::dropScene(0.5f, test::kDeviceSimulation));
    test::expectReboundHeight(w, 0.5f, 0.01f, 0.05f);
}

// One restitution threshold for the CPU rows and the kernels' (rubble/shared/constants.h).
TEST_F(DeviceCases, RestitutionThresholdIsHalfAMetrePerSecond) {
    World above = deviceWorld(test::approachScene(0.75f, test::kDeviceSimulation));
    World below = deviceWorld(test::approachScene(0.35f, test::kDeviceSimulation));
    test::expectRestitutionThreshold(above, below);
}

// A sleeping body that a waking one touches wakes before the rows (kernels/sleep.cl,
// wakeTouched), so that its mass takes part in the solve.
TEST_F(DeviceCases, SleepingRowTakesTheHitWithItsMomentum) {
    World w = deviceWorld(test::sleepingRowScene(test::kDeviceSimulation));
    test::expectSleepingRowTakesTheHit(w, 1e-3);
}
// Boxes resting against each other: the particle paths collide once a step, so a body woken
// in a step meets the next sleeping one only in the step after (no row joins two sleeping
// bodies); it moves into it by up to a step's travel and is pushed back out, and the momentum
// stays, with Jacobi (whose contacts start at overlap) and with PGS.
TEST_F(DeviceCases, TouchingSleepingRowTakesTheHitWithItsMomentum) {
    World w = deviceWorld(test::sleepingRowScene(test::kDeviceSimulation, 0.0));
    test::expectSleepingRowTakesTheHit(w, 1e-3);
    EXPECT_GT(w.body(6).position.x, 4.0f + 0.1f) << "the last box of the row moves";
}
TEST_F(DeviceCases, ParticlePgsTouchingSleepingRowTakesTheHitWithItsMomentum) {
    const std::string pgs =
        R"(, "collision": {"method": "particles", "particle_spacing": 0.1},
           "solver": {"type": "pgs", "iterations": 10})";
    World w = deviceWorld(test::sleepingRowScene(pgs, 0.0));
    test::expectSleepingRowTakesTheHit(w, 1e-3);
    EXPECT_GT(w.body(6).position.x, 4.0f + 0.1f) << "the last box of the row moves";
}
TEST_F(DeviceCases, ElasticBallHittingASleepingOneStopsAndPassesItsVelocityOn) {
    World w = deviceWorld(test::cradleScene(test::kDeviceSimulation));
    test::expectCradleExchange(w, 1e-3f);
}
TEST_F(DeviceCases, ExplosionIntoASleepingRowKeepsItsMomentum) {
    World w = deviceWorld(test::explodedRowScene(test::kDeviceSimulation));
    test::expectExplodedRowKeepsItsMomentum(w, 1e-3);
}

// The CPU twin wakes the same bodies at the same step (host/dynamics/sleep.cpp, wakeTouched):
// the deterministic device run of the exploded row equals it to 1e-5 m at every step.
TEST_F(DeviceCases, SleepingRowWakesAsItsCpuTwinDoes) {
    const std::string scene = test::explodedRowScene(test::kDeviceSimulation);
    World gpuWorld = deviceWorld(scene, true);
    World cpu = test::worldFromText(scene);
    ASSERT_EQ(cpu.options().solver.type, SolverType::Jacobi);
    bool woke = false;
    for (int i = 0; i < 150; ++i) {
        ASSERT_TRUE(cpu.step().ok());
        ASSERT_TRUE(gpuWorld.step().ok());
        for (std::uint32_t b = 1; b < cpu.bodyCount(); ++b) {
            ASSERT_EQ(cpu.body(b).asleep, gpuWorld.body(b).asleep) << "step " << i << " body " << b;
            ASSERT_LT(glm::length(cpu.body(b).position - gpuWorld.body(b).position), 1e-5f)
                << "step " << i << " body " << b;
        }
        woke = woke || (i > 60 && !cpu.body(5).asleep);
    }
    EXPECT_TRUE(woke) << "the last box of the row woke";
}

// SAT and PGS on the device: the CPU's rows (pgsContactRowItem, bounce speed and lift from the
// approach before the forces), the restitution pass after the positions moved (bouncePgs) and
// the lift in the split pass, so the rebound meets the reference's bound (1 mm).
TEST_F(DeviceCases, SatElasticBallReboundsToItsDropHeight) {
    World w = deviceWorld(test::dropScene(1.0f, test::kDeviceSatSimulation));
    test::expectReboundHeight(w, 1.0f, 0.001f, 0.001f);
}
TEST_F(DeviceCases, SatHalfElasticBallReboundsToAQuarterOfItsDropHeight) {
    World w = deviceWorld(test::dropScene(0.5f, test::kDeviceSatSimulation));
    test::expectReboundHeight(w, 0.5f, 0.001f, 0.001f);
}
TEST_F(DeviceCases, SatRestitutionThresholdIsHalfAMetrePerSecond) {
    World above = deviceWorld(test::approachScene(0.75f, test::kDeviceSatSimulation));
    World below = deviceWorld(test::approachScene(0.35f, test::kDeviceSatSimulation));
    test::expectRestitutionThreshold(above, below);
}
TEST_F(DeviceCases, SatSymplecticSpinTurnsByOmegaTimesT) {
    World w = deviceWorld(test::spinScene("symplectic", test::kDeviceSatSimulation));
    test::expectSpinTurnsByOmegaTimesT(w);
}

// Waking before the solve with SAT: the sleeping bodies a pair joins to a restless one wake
// before the rows (with islands, their whole island: DeviceIslands::wake) and the
// collision runs again, so that their mass takes part, to the reference's bounds.
TEST_F(DeviceCases, SatSleepingRowTakesTheHitWithItsMomentum) {
    World w = deviceWorld(test::sleepingRowScene(test::kDeviceSatSimulation));
    test::expectSleepingRowTakesTheHit(w, 1e-3);
}
// Each body sleeping by itself (kernels/sleep.cl, wakeTouchedPairs): a pair of a sleeping body
// and a waking one wakes the sleeping one, to the same bounds.
TEST_F(DeviceCases, SatBodySleepSleepingRowTakesTheHitWithItsMomentum) {
    World w = bodySleepWorld(test::sleepingRowScene(test::kDeviceSatSimulation));
    test::expectSleepingRowTakesTheHit(w, 1e-3);
}
// With the boxes resting against each other the hit reaches through all five before the solve,
// as the CPU wakes the island (islands: the island they fell asleep as; each body by
// itself: wakeStillPairs over last step's entries, the still pairs carried while they sleep):
// woken one contact deep, the second box would meet the first as a wall and the 2 kg m/s be
// gone.
TEST_F(DeviceCases, SatTouchingSleepingRowTakesTheHitWithItsMomentum) {
    World islands = deviceWorld(test::sleepingRowScene(test::kDeviceSatSimulation, 0.0));
    World bodies = bodySleepWorld(test::sleepingRowScene(test::kDeviceSatSimulation, 0.0));
    for (World* w : {&islands, &bodies}) {
        SCOPED_TRACE(w == &islands ? "islands" : "body sleep");
        test::expectSleepingRowTakesTheHit(*w, 1e-3);
        EXPECT_GT(w->body(6).position.x, 4.0f + 0.1f) << "the last box of the row moves";
    }
}
// The same with the first two boxes joined: the hit wakes them as one (an island; each body by
// itself, a joint group, wakeJointGroups, whose members carry the round on), so the wake goes
// on from the second box.
TEST_F(DeviceCases, SatTouchingRowWithAJointTakesTheHitWithItsMomentum) {
    World islands = deviceWorld(test::jointedRowScene(test::kDeviceSatSimulation));
    World bodies = bodySleepWorld(test::jointedRowScene(test::kDeviceSatSimulation));
    for (World* w : {&islands, &bodies}) {
        SCOPED_TRACE(w == &islands ? "islands" : "body sleep");
        test::expectSleepingRowTakesTheHit(*w, 1e-3);
        EXPECT_GT(w->body(6).position.x, 4.0f + 0.1f) << "the last box of the row moves";
    }
}

// The still-pair kernels' bytes (host/gpu/traffic.cpp) come from the entries the device reports
// it kept and carried (the status block): with the touching row asleep and the striker sliding
// towards it alone, a step finds one pair (striker, floor) and carries the row's nine still
// pairs (five on the floor, four between boxes) after it, so the next step's kernels read ten
// entries. In the hit, each launch of wakeStillPairs reads last step's entries (bodies sleeping
// each by itself: with islands the hit wakes the row's island without it).
TEST_F(DeviceCases, SatStillPairKernelsCountTheEntriesTheyRead) {
    World w = bodySleepWorld(test::sleepingRowScene(test::kDeviceSatSimulation, 0.0));
    for (int i = 0; i < 41; ++i) ASSERT_TRUE(w.step().ok());
    for (std::uint32_t i = 2; i < w.bodyCount(); ++i) ASSERT_TRUE(w.body(i).asleep) << i;
    gpu::TrafficCounts n;
    n.pairs = 1;
    n.kept = 10;
    n.carried = 9;
    n.sortItems = context()->workSizes().sortItems;
    std::map<std::string, DeviceCommandTime> before = test::deviceProfileByName(w);
    ASSERT_TRUE(w.step().ok());
    std::map<std::string, DeviceCommandTime> after = test::deviceProfileByName(w);
    for (const auto& [name, id] :
         {std::pair{"markStillPairs", gpu::KernelId::MarkStillPairs},
          {"placeStillPairs", gpu::KernelId::PlaceStillPairs},
          {"carryStillPairs", gpu::KernelId::CarryStillPairs}}) {
        EXPECT_EQ(after[name].launches - before[name].launches, 1u) << name;
        EXPECT_GT(gpu::kernelBytes(id, n), 0u) << name;
        EXPECT_EQ(after[name].bytes - before[name].bytes, gpu::kernelBytes(id, n)) << name;
    }
    // The hit: the striker meets the row between steps 58 and 62.
    std::uint64_t wakes = 0;
    for (int step = 0; step < 40 && wakes == 0; ++step) {
        before = test::deviceProfileByName(w);
        ASSERT_TRUE(w.step().ok());
        after = test::deviceProfileByName(w);
        wakes = after["wakeStillPairs"].launches - before["wakeStillPairs"].launches;
    }
    ASSERT_GT(wakes, 0u) << "the hit runs the wake through the row";
    const std::uint64_t bytes = after["wakeStillPairs"].bytes - before["wakeStillPairs"].bytes;
    std::printf("[ still pairs ] wake: %llu launches, %llu bytes\n", (unsigned long long)wakes,
                (unsigned long long)bytes);
    EXPECT_EQ(bytes, wakes * gpu::kernelBytes(gpu::KernelId::WakeStillPairs, n));
}

// Every kernel of the SAT path counts the bytes it moves, so that `rubble devices --bandwidth`
// sets each against the copy bandwidth: the jointed touching row runs the joints' kernels (rows,
// the projection of a group as one, the joint groups' sleep and wake), the still pairs' carry
// and the wake through them. Bodies sleeping each by itself, which runs every kernel of the SAT
// path but the islands' (IslandsTwin.IslandKernelsCountTheirBytes counts those).
TEST_F(DeviceCases, SatEveryKernelCountsItsBytes) {
    World w = bodySleepWorld(test::jointedRowScene(test::kDeviceSatSimulation));
    for (int i = 0; i < 120; ++i) ASSERT_TRUE(w.step().ok());
    int kernels = 0;
    for (const DeviceCommandTime& c : w.deviceProfile()) {
        if (c.name.empty() || c.name.front() == '(') continue; // transfers count their own
        ++kernels;
        EXPECT_GT(c.bytes, 0u) << c.name << " (" << c.launches << " launches)";
    }
    for (const char* name :
         {"projectJointGroups", "wakeJointGroups", "carryStillPairs", "wakeStillPairs", "solvePgs"})
        EXPECT_GT(test::deviceProfileByName(w)[name].launches, 0u) << name;
    EXPECT_GT(kernels, 30);
}

// A pebble onto a sleeping stack of ten: the hit wakes the whole stack before the solve and its
// contacts start from the impulses they held when they fell asleep (carryStillPairs), so the
// stack gives as the CPU's island does, with islands and with each body sleeping by
// itself. Woken one contact deep the stack would stand as a wall (no sag, the pebble stopped
// dead); woken whole with cold contacts it would sag further.
TEST_F(DeviceCases, SatPebbleOnASleepingStackMovesItAsTheCpuDoes) {
    const std::string scene = test::pebbleOnStackScene(test::kDeviceSatSimulation);
    World device = deviceWorld(scene);
    World cpu = test::worldFromText(scene);
    const test::PebbleHit d = test::pebbleHit(device), c = test::pebbleHit(cpu);
    std::printf(
        "[ pebble on a sleeping stack ] sag %.4f m (cpu %.4f), pebble %.3f m/s (cpu %.3f)\n",
        double(d.sag), double(c.sag), double(d.pebbleSpeed), double(c.pebbleSpeed));
    EXPECT_GT(c.sag, 0.005f) << "the CPU's stack gives under the hit";
    EXPECT_NEAR(d.sag, c.sag, 0.004f) << "m of sag, device against CPU";
    EXPECT_NEAR(d.pebbleSpeed, c.pebbleSpeed, 0.05f) << "m/s of the pebble, device against CPU";
}
TEST_F(DeviceCases, SatElasticBallHittingASleepingOneStopsAndPassesItsVelocityOn) {
    World w = deviceWorld(test::cradleScene(test::kDeviceSatSimulation));
    test::expectCradleExchange(w, 1e-3f);
}
TEST_F(DeviceCases, SatExplosionIntoASleepingRowKeepsItsMomentum) {
    World w = deviceWorld(test::explodedRowScene(test::kDeviceSatSimulation));
    test::expectExplodedRowKeepsItsMomentum(w, 1e-3);
}

// The layer pass on the device (kernels/pgs_push.cl, layerPgs): 100 kg on 1 kg, and on two 1 kg
// boxes, stand at 10 iterations and sleep, to the reference's bounds; 1:10 closer still.
TEST_F(DeviceCases, SatHeavyBoxOnALightOneStands) {
    World w = deviceWorld(test::massStackScene({1.0, 100.0}, test::kDeviceSatSimulation));
    test::expectStackStands(w, 0.01f, 0.05f);
}
TEST_F(DeviceCases, SatHeavyBoxOnTwoLightOnesStands) {
    World w = deviceWorld(test::massStackScene({1.0, 1.0, 100.0}, test::kDeviceSatSimulation));
    test::expectStackStands(w, 0.01f, 0.08f);
}
TEST_F(DeviceCases, SatSmallerRatiosStand) {
    World even = deviceWorld(test::massStackScene({1.0, 1.0}, test::kDeviceSatSimulation));
    test::expectStackStands(even, 0.001f, 0.005f);
    World ten = deviceWorld(test::massStackScene({1.0, 10.0}, test::kDeviceSatSimulation));
    test::expectStackStands(ten, 0.002f, 0.005f);
}

// The drop on the device follows the CPU reference step by step: one pair, so the sweep order
// is the same, and the bounce lands within 1e-4 m of it at every step.
TEST_F(DeviceCases, SatDropFollowsTheCpu) {
    const std::string scene = test::dropScene(0.5f, test::kDeviceSatSimulation);
    World device = deviceWorld(scene, true);
    World cpu = test::worldFromText(scene);
    float worst = 0.0f;
    for (int i = 0; i < 150; ++i) {
        ASSERT_TRUE(cpu.step().ok());
        ASSERT_TRUE(device.step().ok());
        const float d = glm::length(cpu.body(1).position - device.body(1).position);
        worst = std::max(worst, d);
        ASSERT_LT(d, 1e-4f) << "step " << i;
    }
    std::printf("[ drop, cpu against sat+pgs on the device ] largest distance %.3g m\n",
                double(worst));
}

} // namespace
} // namespace rubble
