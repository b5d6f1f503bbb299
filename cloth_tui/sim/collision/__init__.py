"""Contacts: the floor and one module per shape behind a registry (shapes/), swept contacts,
self-collision, held particles."""
