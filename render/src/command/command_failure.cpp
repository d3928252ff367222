#include "command/command_failure.hpp"

#include <cstdio>
#include <new>
#include <stdexcept>

#include "sphray/particles/particles.hpp"
#include "sphray/render/image_file.hpp"
#include "sphray/render/memory_check.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

void report(const std::string& message) {
  std::fprintf(stderr, "sphray: %s\n", message.c_str());
}

int report_failure(const std::string& out_of_memory) {
  try {
    throw;
  } catch (const SceneError& e) {
    report(e.what());
    return kExitUsage;
  } catch (const particles::ParticleError& e) {
    report(e.what());
    return kExitUsage;
  } catch (const std::invalid_argument& e) {  // OutputRefused among them
    report(e.what());
    return kExitUsage;
  } catch (const IoError& e) {
    report(e.what());
    return kExitIo;
  } catch (const InsufficientMemory& e) {
    report(e.what());
    return kExitIo;
  } catch (const std::bad_alloc&) {
    report(out_of_memory);
    return kExitIo;
  }
}

}  // namespace sphray::render
