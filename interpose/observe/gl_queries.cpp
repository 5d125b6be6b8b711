// The app's own queries: ours on the same target step aside, and the app never sees ours.
#include "context_state.hpp"
#include "hooks_generated.hpp"

namespace glbudget {

void handle_glBeginQuery(pfn_glBeginQuery real, GLenum target, GLuint id) {
  ContextState* c = current_context();
  if (c) c->counter->app_query_begin(target);
  real(target, id);
}

void handle_glEndQuery(pfn_glEndQuery real, GLenum target) {
  real(target);
  ContextState* c = current_context();
  if (c) c->counter->app_query_end(target);
}

void handle_glBeginQueryIndexed(pfn_glBeginQueryIndexed real, GLenum target, GLuint index, GLuint id) {
  ContextState* c = current_context();
  if (c && index == 0) c->counter->app_query_begin(target);
  real(target, index, id);
}

void handle_glEndQueryIndexed(pfn_glEndQueryIndexed real, GLenum target, GLuint index) {
  real(target, index);
  ContextState* c = current_context();
  if (c && index == 0) c->counter->app_query_end(target);
}

// GL_CURRENT_QUERY must report the app's view: no active query where only ours is active.
void handle_glGetQueryiv(pfn_glGetQueryiv real, GLenum target, GLenum pname, GLint* params) {
  real(target, pname, params);
  ContextState* c = current_context();
  if (c && params && pname == GL_CURRENT_QUERY && c->counter->our_query_active(target)) *params = 0;
}

void handle_glGetQueryIndexediv(pfn_glGetQueryIndexediv real, GLenum target, GLuint index, GLenum pname,
                                GLint* params) {
  real(target, index, pname, params);
  ContextState* c = current_context();
  if (c && params && index == 0 && pname == GL_CURRENT_QUERY && c->counter->our_query_active(target)) *params = 0;
}

}  // namespace glbudget
