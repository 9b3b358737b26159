// Replaced by the geometry sources.
namespace hertzgear { int meshing_placeholder = 0; }
