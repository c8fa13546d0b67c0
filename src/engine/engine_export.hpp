// The engine's code that does not depend on the scene is compiled once, into the program, and a
// kernel of K built at run time calls it there instead of compiling it again (docs/performance.md,
// "First build of a new K"). Such classes are marked CS_ENGINE_EXPORT; the program exports their
// symbols to the kernels it loads (src/engine_exports.list), and nothing else. Class templates
// are instantiated for 1 to 3 degrees of freedom (phase dimension N = 2, 4, 6): the header says
// `extern template` for those, the program's .cpp instantiates them, and a kernel of a larger
// scene instantiates its own.
#pragma once

#define CS_ENGINE_EXPORT [[gnu::visibility("default")]]
