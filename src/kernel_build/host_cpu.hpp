// The CPU a kernel is compiled for. Kernels of custom scenes are compiled with the program's
// flags, -march=native among them, so a kernel built on one machine may use instructions
// another lacks. A cache shared between machines (a home directory seen from a cluster's login
// node and its partitions) must then keep one kernel per kind of CPU: its key includes this.
#pragma once

#include <istream>
#include <string>

namespace cs {

// The /proc/cpuinfo lines that decide what -march=native means, each field's first occurrence:
// vendor, family, model and name, and the feature flags (x86: vendor_id, cpu family, model,
// model name, flags; Arm: CPU implementer, architecture, variant, part, Features; POWER: cpu;
// s390x: features, facilities; RISC-V: isa, uarch). Fields that differ between cores or over
// time (clock, core ids, bogomips) are left out. Empty if the text has none of them.
std::string cpu_identity(std::istream& cpuinfo);

// cpu_identity() of this host's /proc/cpuinfo, read once; empty where there is none.
const std::string& host_cpu_identity();

}  // namespace cs
