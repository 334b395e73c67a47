/* Preloaded into the sanitizer runs (.ci/sanitize): dlclose keeps every library mapped.
 *
 * The Vulkan loader unloads the driver (lavapipe) and the validation layer when the last instance
 * is destroyed. LeakSanitizer reports at exit, when their code is gone: a leak allocated inside
 * them shows as "(<unknown module>)", and no suppression can name it. With the libraries still
 * mapped, the report names the module and the function, and .ci/sanitizer-suppressions/lsan.supp
 * can say which third-party leak it is and why it is not harmonia's. (Newer loaders offer
 * VK_LOADER_DISABLE_DYNAMIC_LIBRARY_UNLOADING for this; Debian 12's 1.3.239 does not.) */
int dlclose(void *handle) {
  (void)handle;
  return 0;
}
