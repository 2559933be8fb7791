// Placeholder translation unit removed once the first capability lands.
