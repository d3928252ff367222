// sphray: fast, exact ray/sphere intersection. This header includes the whole public contract.
#pragma once

#include "sphray/all_hits.hpp"
#include "sphray/bvh.hpp"
#include "sphray/isa.hpp"
#include "sphray/point_queries.hpp"
#include "sphray/query.hpp"
#include "sphray/ray.hpp"
#include "sphray/ray_arrays.hpp"
#include "sphray/spheres.hpp"
#include "sphray/vec3.hpp"
#include "sphray/version.hpp"
