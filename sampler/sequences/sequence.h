#pragma once
// Low-discrepancy and random sequences behind one small interface: the value
// of point `index`, dimension `dim`, of randomized instance `instance`.
//
// Index conventions (they change L2* by tens of percent, so they are fixed):
//  - Sobol and Halton start at index 0, which is the origin when unscrambled;
//    the first N points are indices 0..N-1.
//  - Halton dimension j uses the j-th prime (2, 3, 5, ...).
//  - pmj02 is two-dimensional: dimension d is coordinate d % 2 of the
//    sequence of pair d / 2 (pmj02.h), randomized per pair.
// Stratified and lattice sets (stratified.h, lattice.h) are sets of N, not
// sequences: their points depend on N, so they have no point `index`, only
// whole sets (generatePoints, generateSet, generatePointSet), each in the
// random order of its seed.
// Each instance k of a randomized sequence uses the seed hash(seed, k).

#include <cstdint>
#include <span>
#include <string>

#include "sampler/point.h"

namespace nuld {

enum class SequenceKind { Sobol, Halton, Random, Stratified, Pmj02, Lattice };
enum class Scramble { None, Owen, Shift, CranleyPatterson, Baker };

inline constexpr auto kSequenceKindNames =
    enumTable<SequenceKind>("sequence", {{"sobol", SequenceKind::Sobol},
                                         {"halton", SequenceKind::Halton},
                                         {"random", SequenceKind::Random},
                                         {"independent", SequenceKind::Random},
                                         {"stratified", SequenceKind::Stratified},
                                         {"pmj02", SequenceKind::Pmj02},
                                         {"lattice", SequenceKind::Lattice}});
inline constexpr auto kScrambleNames =
    enumTable<Scramble>("scrambling", {{"owen", Scramble::Owen},
                                       {"shift", Scramble::Shift},
                                       {"cp", Scramble::CranleyPatterson},
                                       {"baker", Scramble::Baker},
                                       {"none", Scramble::None}});
constexpr const auto &enumNames(SequenceKind) { return kSequenceKindNames; }
constexpr const auto &enumNames(Scramble) { return kScrambleNames; }
inline SequenceKind parseSequenceKind(const std::string &s) { return kSequenceKindNames.parse(s); }
inline Scramble parseScramble(const std::string &s) { return kScrambleNames.parse(s); }

struct SequenceOptions {
  SequenceKind kind = SequenceKind::Sobol;
  Scramble scramble = Scramble::Owen;
  std::uint64_t seed = 0;
};

// The randomization a kind takes when none is asked for: owen for the
// digital sequences (Sobol, Halton, pmj02), cp (its random toroidal shift)
// for the lattice, none for stratified sets (their jitter randomizes them)
// and random points.
Scramble defaultScramble(SequenceKind kind);

// What each kind accepts (every function below throws std::invalid_argument
// naming the scrambling, the sequence and what is expected otherwise):
//  - sobol, halton: all four; random: any (it ignores it);
//  - stratified: none only (the jitter, one uniform point per cell, is its
//    randomization);
//  - pmj02: owen (nested scrambling of a base sequence the seed picks),
//    shift (a digital shift of it) or none (one fixed base sequence); not
//    cp, a toroidal shift, which would break its (0,2) nets;
//  - lattice: cp or shift, both its random toroidal shift (a digital shift
//    would break the lattice), baker (that shift, then the baker's
//    transform of each coordinate: lattice.h), or none (unshifted, in index
//    order); baker applies to the lattice only.
void checkScramble(const SequenceOptions &o);

// Whether two instances of `o` differ: random and stratified sets always,
// the others when scrambled.
bool randomizesInstances(const SequenceOptions &o);

// The p-th prime, p = 0, 1, ... (at least the first 1000 are available).
std::uint32_t nthPrime(std::uint32_t p);

// The scrambling seed of one dimension of one instance of a randomized set:
// independent keys for distinct (seed, instance, dim). Two dependent mixes,
// not hash3's five: the renderer derives two per pixel and dimension pair.
std::uint64_t dimensionSeed(std::uint64_t seed, std::uint32_t instance, std::uint32_t dim);

// Throws std::invalid_argument for the sets of N (stratified, lattice).
double sequenceSample(const SequenceOptions &o, std::uint64_t index, std::uint32_t dim,
                      std::uint32_t instance = 0);

// Points 0..out.size()-1 in dimensions (firstDim, firstDim + 1); for a set
// of N (stratified, lattice) the set of N = out.size() of (instance, firstDim).
void generatePoints(const SequenceOptions &o, std::uint32_t instance, std::span<Point2> out,
                    std::uint32_t firstDim = 0);

// The same points as one set of N = out.size(): Owen scrambling draws the
// digits below those that tell the N points apart with one hash (see
// owenScramble), so the set has the same distribution as generatePoints'
// but costs a few hashes per coordinate instead of 32 to 54. The renderer's
// backends, which scramble every pixel afresh, use this. pmj02 from an even
// firstDim is pmj02Set's set of its pair; stratified and lattice sets are
// generatePoints' own.
void generateSet(const SequenceOptions &o, std::uint32_t instance, std::span<Point2> out,
                 std::uint32_t firstDim = 0);

// K instances of N points each, metadata filled in.
PointSet generatePointSet(const SequenceOptions &o, std::size_t n, std::size_t instances);

}  // namespace nuld
