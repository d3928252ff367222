// Splitting spheres between ranks by place: sorted along a Morton (Z-order) curve through the
// box around their centres, then cut into runs of equal count, so that each rank owns a
// compact region of space and similar work. The split depends on the spheres alone, so every
// rank that holds the same spheres computes the same one without talking to the others.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sphray/sphray.hpp"

namespace sphray::mpi {

/// Every id of spheres, ordered along a Morton curve through the box around the finite centres
/// (ties by id); spheres with a NaN or infinite centre first.
std::vector<std::uint32_t> morton_order(SphereView spheres);

/// The ids of the spheres rank `rank` of `ranks` owns, ascending. Spheres with a NaN or
/// infinite centre go with the first run (they are never hit; they keep their ids). Every id of
/// spheres belongs to exactly one rank.
std::vector<std::uint32_t> spatial_share(SphereView spheres, int rank, int ranks);

/// Every rank's spatial_share at once (one sort for all): what a single process playing the
/// ranks needs.
std::vector<std::vector<std::uint32_t>> spatial_shares(SphereView spheres, int ranks);

/// Shares cut by planes (a k-d split): the spheres are halved by count along the longest axis of
/// their centres' box, the ranks in proportion, recursively. The regions are boxes that overlap
/// only by the spheres' radii, where runs of a Morton curve cut at other than powers of eight
/// straddle cells and their boxes overlap widely. Each share ascending; non-finite centres go
/// with rank 0.
///
/// weights: how much each axis's extent counts when a cut chooses its axis (the longest
/// weighted extent is cut; ties go to the lower axis). A renderer passes the absolute
/// components of its camera's horizontal axis, so that the cuts run across the image and every
/// row of the image crosses every region (docs/distributed.md, "Cut across the view").
///
/// probes: rays to balance rather than spheres, a coarse grid of a camera's rays, say. Each
/// cut then lies where the probes that enter either side's region enter the two sides first in
/// the proportion of their ranks (in a dense cloud, a ray mostly ends in the first region it
/// enters), on a boundary of 1,024 slabs of the cell along its axis, each side keeping between
/// a quarter and three quarters of the cell's spheres (for their memory). Costs one pass over
/// the cell's spheres and, per bisection step, one test of each probe against two boxes. Where
/// the probes cannot tell (none enters the cell, a few spheres, centres at one place along the
/// axis), the cut by count.
std::vector<std::vector<std::uint32_t>> plane_shares(SphereView spheres, int ranks,
                                                     Vec3 weights = {1, 1, 1},
                                                     std::span<const Ray> probes = {});

/// Rank `rank`'s share of plane_shares alone: only the cells on its side are split further.
std::vector<std::uint32_t> plane_share(SphereView spheres, int rank, int ranks,
                                       Vec3 weights = {1, 1, 1}, std::span<const Ray> probes = {});

}  // namespace sphray::mpi
