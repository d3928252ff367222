#include "c_api/scene_handle.hpp"

#include <mutex>
#include <new>

namespace sphray::c_api {
namespace {

// The released handles. Only create and release take the lock, never a query. The list is
// reachable for as long as the library is loaded, so leak checkers do not report it.
std::mutex recycle_mutex;
sphray_scene* recycled = nullptr;

sphray_scene* take_recycled() {
  std::lock_guard lock(recycle_mutex);
  sphray_scene* handle = recycled;
  if (handle != nullptr) recycled = handle->next_free;
  return handle;
}

}  // namespace

sphray_scene* adopt(Scene* scene) {
  sphray_scene* handle = take_recycled();
  if (handle == nullptr) handle = new (std::nothrow) sphray_scene;
  if (handle == nullptr) {
    delete scene;
    throw std::bad_alloc();
  }
  handle->scene = scene;
  handle->next_free = nullptr;
  handle->magic = sphray_scene::kLive;
  return handle;
}

void retire(sphray_scene* handle) noexcept {
  delete handle->scene;
  handle->scene = nullptr;
  handle->magic = sphray_scene::kReleased;
  std::lock_guard lock(recycle_mutex);
  handle->next_free = recycled;
  recycled = handle;
}

}  // namespace sphray::c_api
