#pragma once
// Point-set files (docs/architecture.md, "File formats").
//
// Text: one point per line, coordinates separated by spaces. Lines starting
// with '#' either carry metadata ("# key: value"), or start a new set ("# set"
// or a bare "#", the UTK separator); other comments are ignored. All sets must
// have the same size.
//
// Binary (written for names ending in .ptsb; read by its magic number): the
// 8-byte magic "NULDPTS1", uint32 dimension (2), uint64 N, uint64 instances,
// uint32 metadata bytes, metadata as "key=value\n" lines, then the doubles.
//
// Reading errors name the file, the line (text) and what was expected.

#include <string>

#include "sampler/point.h"

namespace nuld {

PointSet readPointSet(const std::string &path);
void writePointSet(const std::string &path, const PointSet &set);  // atomic

void writePointSetText(std::ostream &out, const PointSet &set);

}  // namespace nuld
