// placeholder, filled by its author
