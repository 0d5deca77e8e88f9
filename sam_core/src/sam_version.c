/* The linked library's version (sam_version.h). */
#include "sam/sam_version.h"

const char *sam_version(void)
{
    return SAM_VERSION_STRING;
}

int sam_version_number(void)
{
    return SAM_VERSION_NUMBER;
}
