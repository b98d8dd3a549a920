// Fixture for the snippet compile test: a correct snippet.
// versions: 330, 450
// stages: fragment
float sk_fixture_square(float x) { return x * x; }
