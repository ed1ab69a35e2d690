"""Real-engine adapters and exports: our alpha inside engines that no one here wrote."""
