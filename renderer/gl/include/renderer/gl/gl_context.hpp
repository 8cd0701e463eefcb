#pragma once
// A headless OpenGL 4.5 (floor 4.3) core-profile context through EGL: no window, no X.
// Order of preference:
//   1. the EGL device platform (EGL_EXT_platform_device): the first device whose context
//      is not a software renderer (NVIDIA, AMD, Intel GPUs);
//   2. Mesa's surfaceless platform (llvmpipe on machines without a GPU);
//   3. any device-platform context, then the default display.
// GL functions are loaded through libepoxy. Failure (no libEGL, no display, no context of
// version >= 4.3 with tessellation) throws terrain::Error with one line naming what was
// found, never crashes.
#include <memory>
#include <string>
#include <vector>

namespace renderer {

struct GlDeviceInfo {
  std::string platform;  // "device 0", "surfaceless", "default"
  std::string detail;    // DRM node or EGL device extensions
  std::string renderer;  // GL_RENDERER of a context made on it, or why none was made
  std::string version;   // GL_VERSION, empty when no context
  bool software = false;
  bool usable = false;  // GL >= 4.3 core with tessellation
};

// Every EGL display this machine offers and what a context on it reports.
std::vector<GlDeviceInfo> list_gl_devices();

class GlContext {
 public:
  // Creates and makes current the preferred context (see above). Error when none.
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  const GlDeviceInfo& info() const { return info_; }
  bool has_clip_control() const { return clip_control_; }
  // Makes this context current again (a program that also draws to a window's own
  // context, terrain-view, switches between the two on one thread).
  void make_current() const;
  // Leaves no context of this thread current: libglvnd refuses to make a GLX context
  // current while an EGL one is (BadAccess), so a program with both releases one first.
  void release_current() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  GlDeviceInfo info_;
  bool clip_control_ = false;
};

}  // namespace renderer
