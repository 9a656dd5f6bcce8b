"""The three built-in mechanisms' own textbook closed forms (seed 000's four-bar and shaper, seed 003's
five-bar) and their inverse dynamics: independent checks of the general solver."""
