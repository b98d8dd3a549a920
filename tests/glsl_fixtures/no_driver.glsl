// Fixture for the snippet compile test: declares a vertex stage with no driver file.
// versions: 450
// stages: vertex
float sk_fixture_nodriver(float x) { return x; }
