// Prints the instruction sets the queries and the trees use and the result of one query, for
// the SPHRAY_ISA tests, which run it under different environments.
#include <cstdio>

#include <sphray/sphray.hpp>

int main() {
  sphray::SphereSoA s;
  for (int i = 0; i < 20; ++i)
    s.add({0, 0, -2.0f - i}, 0.5f);
  const sphray::Hit hit = sphray::intersect(s.view(), sphray::Ray{{0, 0, 0}, {0, 0, -1}});
  std::printf("active=%s hit=%u t=%g tree=%s\n",
              std::string(sphray::isa_name(sphray::active_isa())).c_str(), hit.id, hit.t,
              std::string(sphray::isa_name(sphray::bvh_isa(s.size()))).c_str());
  return hit.id == 0 && hit.t == 1.5f ? 0 : 1;
}
