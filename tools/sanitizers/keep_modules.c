/* Preloaded into every process of the sanitizer stage's tests (CMakePresets.json, test preset
 * "asan"): dlclose() keeps the shared object loaded. LeakSanitizer looks for pointers to
 * each allocation at exit, in the globals of the modules still loaded; a driver the Vulkan
 * loader has dlclose()d (lavapipe, its LLVM) takes the globals that hold its caches with it,
 * and what they pointed to is then reported as leaked from "<unknown module>" (128 bytes from
 * realloc on an AMD EPYC host, none on an Intel one). Keeping modules loaded makes that memory
 * reachable again; rtdenoise's own allocations are checked as before. Built without any
 * sanitizer flags (tests/CMakeLists.txt), so that preloading it into uninstrumented programs
 * the tests start (bash, oiiotool) is harmless. */
int dlclose(void* handle) {
  (void)handle;
  return 0;
}
