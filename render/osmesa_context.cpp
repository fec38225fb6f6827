#include "render/osmesa_context.h"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <string>
#include <type_traits>

namespace dw::render {

// OSMesa is opened when a headless context is made rather than linked: it brings LLVM (for
// llvmpipe), 45 MiB of every process that loads it, which most processes never draw with
// (`dwatch check`, `run` without `--render`, every rank of a run over MPI). RTLD_NODELETE keeps it
// loaded once opened, since Mesa and LLVM are not made to be unloaded; each context holds a
// reference.
struct OsMesaContext::Library {
  void* handle = nullptr;
  decltype(&OSMesaCreateContextAttribs) create_context = nullptr;
  decltype(&OSMesaGetProcAddress) get_proc_address = nullptr;
  decltype(&OSMesaGetCurrentContext) current_context = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaDestroyContext) destroy_context = nullptr;

  // Empty, or why OSMesa could not be opened.
  std::string open() {
    handle = ::dlopen(DWATCH_OSMESA_LIBRARY, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!handle) return std::string("OSMesa (" DWATCH_OSMESA_LIBRARY ") could not be loaded: ") + ::dlerror();
    const auto find = [&](auto& function, const char* name) {
      function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(::dlsym(handle, name));
      return function != nullptr;
    };
    if (!find(create_context, "OSMesaCreateContextAttribs") || !find(get_proc_address, "OSMesaGetProcAddress") ||
        !find(current_context, "OSMesaGetCurrentContext") || !find(make_current, "OSMesaMakeCurrent") ||
        !find(destroy_context, "OSMesaDestroyContext"))
      return std::string(DWATCH_OSMESA_LIBRARY " lacks a function: ") + ::dlerror();
    return {};
  }
  ~Library() {
    if (handle) ::dlclose(handle);
  }
};

OsMesaContext::OsMesaContext() : library_(std::make_unique<Library>()) {}

std::variant<std::unique_ptr<OsMesaContext>, std::string> OsMesaContext::create() {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            0,  // depth lives in the renderer's framebuffers
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            3,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            3,
                            0};
  std::unique_ptr<OsMesaContext> c(new OsMesaContext());
  if (std::string why = c->library_->open(); !why.empty()) return why;
  c->context_ = c->library_->create_context(attributes, nullptr);
  if (!c->context_) return std::string("OSMesa could not create an OpenGL 3.3 core context");
  c->make_current();
  std::string missing = load_gl(c->gl_, c->library_->get_proc_address);
  if (!missing.empty()) return "the OSMesa context lacks " + missing;
  return c;
}

OsMesaContext::~OsMesaContext() {
  if (!context_) return;
  const Library& mesa = *library_;
  if (mesa.current_context() == static_cast<OSMesaContext>(context_)) mesa.make_current(nullptr, nullptr, 0, 0, 0);
  mesa.destroy_context(static_cast<OSMesaContext>(context_));
}

void OsMesaContext::make_current() {
  library_->make_current(static_cast<OSMesaContext>(context_), pixel_, GL_UNSIGNED_BYTE, 1, 1);
}

}  // namespace dw::render
