// Putting together the parts that the shards of a surfelize run wrote on several machines.
#pragma once

#include <filesystem>
#include <span>

namespace pbs {

// Writes `output` from `parts`, one part of every shard of one plan (SurfelizeOptions::shard), in any
// order: the whole .surfels file, byte for byte what one surfelizeToFile with the same options writes.
// Each array's record and stored data are copied from the part that holds it, every chunk's checksum
// checked. Every part is opened and checked before anything is written, and the file is written under a
// temporary name and renamed, so a refused or failed merge leaves no `output` behind (nor changes one
// already there). Throws InputError naming the part and its shard for a part that is not one (a whole
// file), one of another scene, made with other options or of another plan than the first part, a shard
// given twice, a missing shard (naming `output`), or a corrupt part (truncated, a checksum that does not
// match).
void mergeSurfelParts(std::span<const std::filesystem::path> parts, const std::filesystem::path& output);

}  // namespace pbs
