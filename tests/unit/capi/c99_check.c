/* include/sdv/sdv.h compiles as strict C99 (the capi/c99_header test). */
#include "sdv/sdv.h"

int main(void) {
    sdv_config cfg = {sizeof(sdv_config), "x.sdv", 0, 0, 0, 0, 0, 0, 1};
    sdv_sim* sim = 0;
    return sdv_create(&cfg, &sim) == SDV_OK ? 0 : (int)sdv_api_version() - SDV_API_VERSION;
}
