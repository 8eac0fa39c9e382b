"""Encodings: machines as automata, networks of them, and their symbolic transition system over Z3."""
