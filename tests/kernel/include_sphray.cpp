// Includes the whole public C++ contract and nothing else: compiled by headers.need_cxx20.
#include <sphray/sphray.hpp>
