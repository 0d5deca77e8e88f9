/*
 * Preloaded into GL tests in sanitizer builds only. eglTerminate unloads
 * Mesa's driver, after which LeakSanitizer reports the driver's global
 * allocations as leaks from an "<unknown module>" it can neither symbolize
 * nor suppress. Keeping modules mapped leaves those allocations reachable,
 * so leak checking still covers the project's own code in GL tests.
 */
#include <dlfcn.h>

int dlclose(void *handle)
{
    (void)handle;
    return 0;
}
