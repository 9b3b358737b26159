// Replaced by the dynamics sources.
namespace hertzgear { int dynamics_placeholder = 0; }
