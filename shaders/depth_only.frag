// Depth pre-pass of opaque surfaces: depth only, so the lighting pass shades each pixel once.
void main() {}
