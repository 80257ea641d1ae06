// tests/unit/particle_keys_test.cpp: rubble/shared/particle.h's search for last step's place of
// a particle contact (findParticleKeyItem, which particlePairs runs on the device) against a
// brute-force scan, from every starting hint.
#include "rubble/shared/particle.h"

#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace rubble {
namespace {

using shared::ParticleContactKey;

bool same(const ParticleContactKey& x, const ParticleContactKey& y) {
    return !shared::particleKeyLessItem(x, y) && !shared::particleKeyLessItem(y, x);
}

// The place of `key` among `keys` by looking at each, or keys.size().
std::uint32_t scan(const std::vector<ParticleContactKey>& keys, const ParticleContactKey& key) {
    for (std::uint32_t i = 0; i < keys.size(); ++i)
        if (same(keys[i], key)) return i;
    return std::uint32_t(keys.size());
}

ParticleContactKey randomKey(std::mt19937& rng) {
    // Few bodies and particles, so that keys share pairs and particles and some repeat.
    std::uniform_int_distribution<std::uint32_t> body(0, 5), particle(0, 9);
    const std::uint32_t a = body(rng), b = body(rng);
    return ParticleContactKey{std::min(a, b), std::max(a, b), particle(rng), particle(rng)};
}

TEST(ParticleKeys, TheSearchFromAnyHintFindsWhatAScanFinds) {
    std::mt19937 rng(7);
    for (const std::uint32_t count : {0u, 1u, 2u, 3u, 5u, 17u, 64u, 200u}) {
        std::vector<ParticleContactKey> keys;
        for (std::uint32_t i = 0; i < count; ++i) keys.push_back(randomKey(rng));
        std::sort(keys.begin(), keys.end(),
                  [](const auto& x, const auto& y) { return shared::particleKeyLessItem(x, y); });
        // Last step's keys are distinct (one contact per pair of particles).
        keys.erase(std::unique(keys.begin(), keys.end(), same), keys.end());
        const std::uint32_t n = std::uint32_t(keys.size());
        // Keys that are there and keys that are not, before, between and after them.
        std::vector<ParticleContactKey> asked(keys);
        for (int i = 0; i < 60; ++i) asked.push_back(randomKey(rng));
        asked.push_back(ParticleContactKey{0, 0, 0, 0});
        asked.push_back(ParticleContactKey{9, 9, 99, 99});
        for (const ParticleContactKey& key : asked)
            for (std::uint32_t hint = 0; hint <= n + 2; ++hint)
                ASSERT_EQ(shared::findParticleKeyItem(key, hint, n, keys.data()), scan(keys, key))
                    << count << " keys, hint " << hint << ", key (" << key.lower << ", "
                    << key.higher << ", " << key.particleA << ", " << key.featureB << ")";
    }
}

} // namespace
} // namespace rubble
