// The Python module `quack` (docs/python.md).

#include "bindings.hpp"

PYBIND11_MODULE(quack, m) {
  m.doc() =
      "Quack: 2D collision detection and response. Shapes (quack.circle, ...), the pair "
      "queries of `quack query` (quack.distance, ...), batch queries over numpy arrays "
      "(quack.distance_many, ...) and worlds (quack.World, quack.load_scene); in 3D the "
      "submodule quack.d3 (shapes, pair and batch queries). "
      "Units: metres, kilograms, seconds, radians; poses are (x, y, angle). Constants: "
      "ALL_CATEGORIES (every category bit), BODY_STATE_COLUMNS (the columns of "
      "World.body_state), GJK_STATUSES and EPA_STATUSES (the status codes of batch results). "
      "Typed: the stub package quack-stubs (python/stubs/quack/). See docs/python.md.";
  m.attr("__version__") = QUACK_VERSION;
  quack::python::registerShapes(m);
  quack::python::registerQueries(m);
  quack::python::registerBatch(m);
  quack::python::registerWorld(m);
  quack::python::registerD3(m);
}
