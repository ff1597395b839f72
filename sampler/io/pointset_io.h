#pragma once
// Point-set files (docs/architecture.md, "File formats").
//
// Text: one point per line, coordinates separated by spaces. Lines starting
// with '#' either carry metadata ("# key: value"), or start a new set ("# set"
// or a bare "#", the UTK separator); other comments are ignored. All sets must
// have the same size.
//
// Binary (written for names ending in .ptsb; read by its magic number): the
// 8-byte magic "NULDPTS2", uint32 dimension (2), uint64 N, uint64 instances,
// uint32 metadata bytes, metadata as "key=value\n" lines, the doubles, then
// the uint64 FNV-1a hash (content_hash.h) of every byte before it, which
// every read verifies. "NULDPTS1" files, the same without the hash, are
// still read.
//
// Reading errors name the file, the line (text) and what was expected.

#include <string>

#include "sampler/point.h"

namespace nuld {

PointSet readPointSet(const std::string &path);

// The check every reader of points makes (these files, `nuld eval`, and the
// Python module's arrays): "" for a point with finite coordinates in the
// unit square, else what is wrong ("coordinate is not finite", "point (x, y)
// lies outside the unit square; expected coordinates in [0, 1]").
std::string pointProblem(Point2 p);
void writePointSet(const std::string &path, const PointSet &set);  // atomic

void writePointSetText(std::ostream &out, const PointSet &set);

// The points alone, for numpy and spreadsheets (`nuld export`), atomic; the
// format follows the extension:
//   .npy  float64 array of shape (instances, N, 2), C order (numpy.load);
//   .csv  a header "instance,x,y", then one point per line (numpy.loadtxt
//         with delimiter=',' and skiprows=1 gives (instances * N, 3));
//   .dat  UTK's text format: one point per line, a line "#" between sets
//         (readPointSet reads it back; the text format's metadata lines
//         would read as set separators in UTK).
// Metadata is not written. Throws std::invalid_argument naming the file for
// another extension.
void exportPointSet(const std::string &path, const PointSet &set);

}  // namespace nuld
