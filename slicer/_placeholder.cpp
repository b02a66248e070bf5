// placeholder until the first source lands; replaced in this change
