#pragma once
// Random test boxes for the sampled box discrepancy
// (docs/architecture.md, "The soft box loss").
//
// A box side that lies on the boundary of the unit square is stored as
// -inf / +inf: it is not a side at all, since every point of the domain is on
// the inside of it. This keeps the soft indicator from counting points near
// the domain edge as half inside.

#include <span>
#include <string>

#include "sampler/point.h"
#include "sampler/sequences/rng.h"

namespace nuld {

enum class BoxKind {
  MultipleCorner,  // a random corner c of the square and a uniform opposite corner y
  Anchored,        // [0, y]: the corner at the origin
  TwoPoint,        // the bounding box of two uniform points
};

inline constexpr auto kBoxKindNames =
    enumTable<BoxKind>("box kind", {{"multicorner", BoxKind::MultipleCorner},
                                    {"anchored", BoxKind::Anchored},
                                    {"twopoint", BoxKind::TwoPoint},
                                    {"multiple-corner", BoxKind::MultipleCorner},
                                    {"two-point", BoxKind::TwoPoint}});
constexpr const auto &enumNames(BoxKind) { return kBoxKindNames; }
inline BoxKind parseBoxKind(const std::string &s) { return kBoxKindNames.parse(s); }

// Draws one box; it takes drawsPerBox(kind) values from rng.
Box2 sampleBox(BoxKind kind, Rng &rng);
int drawsPerBox(BoxKind kind);
// out.size() boxes, the same as as many sampleBox calls in a row (rng ends
// where they would leave it), drawn in parallel blocks: the generator is
// counter-based, so each block starts where the boxes before it stop.
void sampleBoxes(BoxKind kind, Rng &rng, std::span<Box2> out);

}  // namespace nuld
