// The Blender program of the Cycles export: export/cycles_scene.py below its
// marker line, byte for byte, embedded at build time (export/CMakeLists.txt,
// export/embed_text.cmake). export_cycles() writes it after the SCENE data.
#pragma once

namespace furnace::exporter {

extern const char kCyclesScenePython[];

}  // namespace furnace::exporter
