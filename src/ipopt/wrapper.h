/* The one header bindgen reads (see build.rs): Ipopt's C interface. */
#include <coin/IpStdCInterface.h>
