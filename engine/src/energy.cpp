// stub: being written
#include <lever/lever.hpp>
