#pragma once
// The fixed values of a neural generator's model-file metadata, shared by
// the writer (NeuralGenerator::metadata) and the reader
// (NeuralSettings::fromModelFile).

namespace nuld {

inline constexpr const char *kModelFormat = "nuld-neural-generator";
inline constexpr int kModelVersion = 1;
// The metadata 'base' of each randomization (files from before the Owen base
// all say the rotated one's).
inline constexpr const char *kRotatedBaseName = "sobol rotated by z";
inline constexpr const char *kOwenBaseName = "sobol owen-scrambled by a hash of z";

}  // namespace nuld
