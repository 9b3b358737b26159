// Replaced by the FE sources.
namespace hertzgear { int fem_placeholder = 0; }
