// Linked into every executable of the sanitizer build (QUADPLAN_SANITIZE) only: dlclose does
// nothing, so libraries the Vulkan loader opens (the driver, the validation layer) stay mapped
// until exit and LeakSanitizer can name them in a stack (and lsan.supp can match them).
// Without it their frames print as "<unknown module>" and nothing can be told apart.
extern "C" int dlclose(void*) { return 0; }
