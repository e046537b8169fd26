#pragma once
// Private: writes "key = value // comment" without MRPT's name padding (padded names would become
// part of the keys that rasm::knownKeys reads back for the strict loader).

#include <mrpt/config/CConfigFileBase.h>

#define RASM_SIM_SAVE(var, comment) c.write(s, #var, var, -1, -1, comment)
