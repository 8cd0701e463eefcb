#include "renderer/gl/gl_context.hpp"

#include <dlfcn.h>
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <fmt/format.h>
#include <algorithm>
#include <cstring>

#include "terrain/error.hpp"

namespace renderer {

namespace {

bool has_ext(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// libepoxy aborts the process when it cannot load libEGL: check first, so that a machine
// without EGL gets an error message instead.
void require_libegl() {
  static const bool ok = [] {
    void* h = dlopen("libEGL.so.1", RTLD_NOW | RTLD_GLOBAL);
    return h != nullptr;
  }();
  if (!ok)
    throw terrain::Error(
        "no OpenGL: libEGL.so.1 cannot be loaded (install libegl1 and a driver: Mesa or a GPU "
        "vendor's)");
}

struct Candidate {
  EGLDisplay display = EGL_NO_DISPLAY;
  GlDeviceInfo info;
};

std::vector<Candidate> candidates() {
  require_libegl();
  std::vector<Candidate> out;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (has_ext(client, "EGL_EXT_device_enumeration") || has_ext(client, "EGL_EXT_device_base")) {
    EGLint n = 0;
    if (eglQueryDevicesEXT(0, nullptr, &n) && n > 0) {
      std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(n));
      eglQueryDevicesEXT(n, devices.data(), &n);
      for (EGLint i = 0; i < n; ++i) {
        Candidate c;
        c.info.platform = fmt::format("device {}", i);
        const char* dext = eglQueryDeviceStringEXT(devices[std::size_t(i)], EGL_EXTENSIONS);
        const char* drm =
            has_ext(dext, "EGL_EXT_device_drm")
                ? eglQueryDeviceStringEXT(devices[std::size_t(i)], EGL_DRM_DEVICE_FILE_EXT)
                : nullptr;
        c.info.detail = drm ? drm : (dext ? dext : "");
        c.info.software = has_ext(dext, "EGL_MESA_device_software");
        c.display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[std::size_t(i)], nullptr);
        out.push_back(c);
      }
    }
  }
  if (has_ext(client, "EGL_MESA_platform_surfaceless")) {
    Candidate c;
    c.info.platform = "surfaceless";
    c.info.detail = "Mesa EGL_MESA_platform_surfaceless";
    c.display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    out.push_back(c);
  }
  Candidate d;
  d.info.platform = "default";
  d.info.detail = "eglGetDisplay(EGL_DEFAULT_DISPLAY)";
  d.display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  out.push_back(d);
  return out;
}

struct Made {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;
  bool clip_control = false;
};

void release(Made& m) {
  if (m.display == EGL_NO_DISPLAY) return;
  eglMakeCurrent(m.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (m.surface != EGL_NO_SURFACE) eglDestroySurface(m.display, m.surface);
  if (m.context != EGL_NO_CONTEXT) eglDestroyContext(m.display, m.context);
  m = Made{};
}

// The newest core context of 4.5, 4.4 and 4.3 that `display` makes, or EGL_NO_CONTEXT.
EGLContext core_context(EGLDisplay display, EGLConfig config) {
  for (const auto& [maj, min] : {std::pair{4, 5}, {4, 4}, {4, 3}}) {
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION,
                            maj,
                            EGL_CONTEXT_MINOR_VERSION,
                            min,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                            EGL_NONE};
    const EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attrs);
    if (context != EGL_NO_CONTEXT) return context;
  }
  return EGL_NO_CONTEXT;
}

// The current context's renderer and version, whether it is a software one and usable (4.3
// or newer).
void describe_context(GlDeviceInfo& info) {
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  info.renderer = r ? r : "?";
  info.version = v ? v : "?";
  for (const char* sw : {"llvmpipe", "softpipe", "SWR", "lavapipe", "Software Rasterizer"})
    if (info.renderer.find(sw) != std::string::npos) info.software = true;
  GLint gl_major = 0, gl_minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
  glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
  info.usable = gl_major > 4 || (gl_major == 4 && gl_minor >= 3);
}

// Tries a 4.5, 4.4 then 4.3 core context on `c.display`, makes it current and fills
// c.info. Returns false (context released) when it is not usable.
bool try_context(Candidate& c, Made& m) {
  m = Made{};
  if (c.display == EGL_NO_DISPLAY) {
    c.info.renderer = "no EGL display";
    return false;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(c.display, &major, &minor)) {
    c.info.renderer = fmt::format("eglInitialize failed (EGL error 0x{:x})", eglGetError());
    return false;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    c.info.renderer = "no desktop OpenGL API on this display";
    return false;
  }
  const char* dext = eglQueryString(c.display, EGL_EXTENSIONS);
  EGLConfig config = EGL_NO_CONFIG_KHR;
  const bool no_config = has_ext(dext, "EGL_KHR_no_config_context");
  const bool surfaceless = has_ext(dext, "EGL_KHR_surfaceless_context");
  if (!no_config || !surfaceless) {
    const EGLint attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                            EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(c.display, attrs, &config, 1, &n) || n < 1) {
      c.info.renderer = "no OpenGL pbuffer config";
      return false;
    }
  }
  m.display = c.display;
  m.context = core_context(c.display, config);
  if (m.context == EGL_NO_CONTEXT) {
    c.info.renderer = "no OpenGL 4.3 core context";
    release(m);
    return false;
  }
  if (!surfaceless) {
    const EGLint pb[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
    m.surface = eglCreatePbufferSurface(c.display, config, pb);
  }
  if (!eglMakeCurrent(c.display, m.surface, m.surface, m.context)) {
    c.info.renderer = "eglMakeCurrent failed";
    release(m);
    return false;
  }
  describe_context(c.info);
  if (!c.info.usable) {
    release(m);
    return false;
  }
  GLint gl_major = 0, gl_minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
  glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
  m.clip_control = gl_major > 4 || gl_minor >= 5 || epoxy_has_gl_extension("GL_ARB_clip_control");
  return true;
}

}  // namespace

struct GlContext::Impl {
  Made made;
};

std::vector<GlDeviceInfo> list_gl_devices() {
  std::vector<GlDeviceInfo> out;
  for (auto& c : candidates()) {
    Made m;
    if (try_context(c, m)) release(m);
    out.push_back(c.info);
  }
  return out;
}

GlContext::GlContext() : impl_(std::make_unique<Impl>()) {
  auto cands = candidates();
  // Hardware devices first, then Mesa's surfaceless platform, then anything usable.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < cands.size(); ++i)
    if (cands[i].info.platform.starts_with("device") && !cands[i].info.software) order.push_back(i);
  for (std::size_t i = 0; i < cands.size(); ++i)
    if (cands[i].info.platform == "surfaceless") order.push_back(i);
  for (std::size_t i = 0; i < cands.size(); ++i)
    if (std::find(order.begin(), order.end(), i) == order.end()) order.push_back(i);

  std::string tried;
  for (const std::size_t i : order) {
    Made m;
    if (try_context(cands[i], m)) {
      impl_->made = m;
      info_ = cands[i].info;
      clip_control_ = m.clip_control;
      return;
    }
    tried += fmt::format("{}{}: {}{}", tried.empty() ? "" : "; ", cands[i].info.platform,
                         cands[i].info.renderer,
                         cands[i].info.version.empty() ? "" : " (" + cands[i].info.version + ")");
  }
  throw terrain::Error("no usable OpenGL 4.3 core context through EGL (tried " + tried + ")");
}

GlContext::~GlContext() { release(impl_->made); }

void GlContext::release_current() const {
  eglMakeCurrent(impl_->made.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

void GlContext::make_current() const {
  const Made& m = impl_->made;
  if (!eglMakeCurrent(m.display, m.surface, m.surface, m.context))
    throw terrain::Error("cannot make the OpenGL context current again (eglMakeCurrent failed)");
}

}  // namespace renderer
