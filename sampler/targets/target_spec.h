#pragma once
// Builds a target from its SPEC string (docs/usage.md, "Point sets";
// docs/architecture.md, "Targets and families"):
//   uniform | bilinear:w00,w10,w01,w11 | gaussian:mx,my,sigma | quarterdisc |
//   step:x0[,left,right] | image:PATH | envmap:PATH
// Other modules add kinds of target (the materials module adds `disney:`) through
// registerTargetKind, so the sampler never depends on them.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sampler/targets/target.h"

namespace nuld {

using TargetFactory = std::function<std::unique_ptr<Target>(const std::string &args)>;

// Adds the kind of target `NAME[:ARGS]` to makeTarget; `grammar` and
// `description` are its line in targetDescriptions.
void registerTargetKind(const std::string &name, TargetFactory factory,
                        const std::string &grammar = "", const std::string &description = "");

// Every kind of target makeTarget knows, built in and registered, as
// (grammar, description) pairs in a fixed order: what `nuld help targets`
// prints and the error for an unknown kind names.
struct TargetDescription {
  std::string grammar, description;
};
std::vector<TargetDescription> targetDescriptions();

// Throws std::invalid_argument naming the spec and what was expected; for
// image: and envmap: a file that cannot be read gives std::runtime_error
// naming the path.
std::unique_ptr<Target> makeTarget(const std::string &spec);
// Refuses (as makeTarget does) a spec whose family no target has, without
// building anything: the grammar check of a --target option.
void checkTargetFamily(const std::string &spec);

// Parses "a,b,c" into exactly `count` numbers (or between min and max).
std::vector<double> parseNumberList(const std::string &spec, const std::string &args,
                                    std::size_t minCount, std::size_t maxCount,
                                    const std::string &expected);

// Whether two target specs name the same target: equal strings, or for
// image:, envmap: and envmap-mean: the same file reached through different
// paths.
bool sameTarget(const std::string &specA, const std::string &specB);

// Records what a set's points follow in its metadata: the target's spec
// (readable, and what rebuilds it), its content hash (Target::contentHash:
// what matches the set to the same target on another machine or under
// another asset root) and its domain.
void recordTarget(PointSet &set, const Target &target);
// Whether a set's recorded target is the target with this spec and content
// hash: the same spec (sameTarget), or the same recorded content hash.
bool followsTarget(const PointSet &set, const std::string &spec, const std::string &contentHash);

// Parses set sizes "16,32,64" (positive, at most 9 digits each, duplicates
// dropped, order kept); throws std::invalid_argument starting with `what`
// (an option or a file's field) and saying what was expected.
std::vector<std::size_t> parseSizeList(const std::string &what, const std::string &text);

}  // namespace nuld
