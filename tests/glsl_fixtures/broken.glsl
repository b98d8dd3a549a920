// Fixture for the snippet compile test: a syntax error (missing semicolon) that must fail.
// versions: 450
// stages: fragment
float sk_fixture_broken(float x) { return x * x }
