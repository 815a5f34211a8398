"""The action grammar, trees in bracket notation, tree files and the action graph."""
